rtt bench /root/.cache/rtt-data/meshes/refined_elephant.off --views bench/views.json --size 1024 --only primary,soft,build --accel bvh --frames 3 --warmup 0 --threads 1,2 --json
# binary: main at a49975e; loadavg before: 1.30 1.19 1.31 1/81 30155
# exit 0; loadavg after: 1.27 1.20 1.30 1/80 30233; Wed Dec  2 19:56:13 UTC 2026
