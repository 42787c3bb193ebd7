rtt bench /root/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
# binary: main at a49975e; loadavg before: 1.52 1.30 1.27 1/80 30362
# exit 0; loadavg after: 1.32 1.27 1.26 1/80 30368; Wed Dec  2 20:13:20 UTC 2026
