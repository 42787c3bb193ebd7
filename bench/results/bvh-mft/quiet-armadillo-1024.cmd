rtt bench /root/.cache/rtt-data/meshes/armadillo.off --views bench/views.json --size 1024 --only primary,soft,build --accel bvh --frames 3 --warmup 0 --threads 1,2 --json
# binary: main at a49975e; loadavg before: 1.36 1.17 1.32 1/81 30144
# exit 0; loadavg after: 1.30 1.19 1.31 1/80 30150; Wed Dec  2 19:54:45 UTC 2026
