rtt bench /root/.cache/rtt-data/meshes/refined_elephant.off --views bench/views.json --size 1024 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
# binary: main at a49975e; loadavg before: 1.29 1.27 1.26 1/80 30401
# exit 0; loadavg after: 1.28 1.26 1.26 1/80 30417; Wed Dec  2 20:14:22 UTC 2026
