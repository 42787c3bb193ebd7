rtt bench /root/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --size 1024 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
# binary: main at a49975e; loadavg before: 1.58 1.30 1.27 1/80 30343
# exit 0; loadavg after: 1.52 1.30 1.27 1/80 30359; Wed Dec  2 20:12:54 UTC 2026
