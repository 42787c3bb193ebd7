rtt bench /root/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --size 1920 --height 1200 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
# binary: main at a49975e; loadavg before: 1.27 1.30 1.27 1/79 30553
# exit 0; loadavg after: 1.29 1.30 1.27 1/79 30569; Wed Dec  2 20:21:14 UTC 2026
