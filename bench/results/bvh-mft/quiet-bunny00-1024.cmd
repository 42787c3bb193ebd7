rtt bench /root/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --size 1024 --only primary,soft,build --accel bvh --frames 3 --warmup 0 --threads 1,2 --json
# binary: main at a49975e; loadavg before: 0.80 1.04 1.31 4/80 29983
# exit 0; loadavg after: 1.36 1.17 1.32 1/81 30140; Wed Dec  2 19:53:08 UTC 2026
