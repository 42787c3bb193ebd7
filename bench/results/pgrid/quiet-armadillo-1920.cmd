rtt bench /root/.cache/rtt-data/meshes/armadillo.off --views bench/views.json --size 1920 --height 1200 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
# binary: main at d181d69; loadavg before: 1.26 1.65 1.80 1/79 23572
# exit 0; loadavg after: 1.29 1.62 1.79 1/79 23581; Wed Dec  2 19:35:02 UTC 2026
