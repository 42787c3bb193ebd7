rtt bench /root/.cache/rtt-data/meshes/refined_elephant.off --views bench/views.json --size 1920 --height 1200 --only shadow,build --frames 5 --threads 1,2 --json
# binary: main at d181d69; loadavg before: 1.60 2.08 1.96 1/74 23355
# exit 0; loadavg after: 1.37 1.98 1.93 1/74 23451; Wed Dec  2 19:31:32 UTC 2026
