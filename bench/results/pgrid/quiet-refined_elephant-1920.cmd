rtt bench /root/.cache/rtt-data/meshes/refined_elephant.off --views bench/views.json --size 1920 --height 1200 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
# binary: main at d181d69; loadavg before: 1.29 1.62 1.79 1/79 23585
# exit 0; loadavg after: 1.26 1.57 1.77 1/79 23594; Wed Dec  2 19:35:30 UTC 2026
