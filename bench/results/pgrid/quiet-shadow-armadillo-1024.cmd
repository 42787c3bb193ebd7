rtt bench /root/.cache/rtt-data/meshes/armadillo.off --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
# binary: main at a49975e; loadavg before: 1.29 1.27 1.26 1/80 30391
# exit 0; loadavg after: 1.29 1.27 1.26 1/80 30397; Wed Dec  2 20:14:04 UTC 2026
