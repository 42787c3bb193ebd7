rtt bench /root/.cache/rtt-data/meshes/armadillo.off --views bench/views.json --size 1920 --height 1200 --only shadow,build --frames 5 --threads 1,2 --json
# binary: main at d181d69; loadavg before: 1.53 2.13 1.97 2/79 23314
# exit 0; loadavg after: 1.60 2.08 1.96 1/74 23351; Wed Dec  2 19:31:01 UTC 2026
