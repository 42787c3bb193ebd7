rtt bench /root/.cache/rtt-data/meshes/refined_elephant.off --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
# binary: main at a49975e; loadavg before: 1.28 1.26 1.26 1/80 30420
# exit 0; loadavg after: 1.34 1.28 1.27 1/80 30426; Wed Dec  2 20:14:46 UTC 2026
