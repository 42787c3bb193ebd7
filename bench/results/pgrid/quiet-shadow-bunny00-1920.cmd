rtt bench /root/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --size 1920 --height 1200 --only shadow,build --frames 5 --threads 1,2 --json
# binary: main at a49975e; loadavg before: 1.29 1.30 1.27 1/79 30572
# exit 0; loadavg after: 1.40 1.34 1.29 1/79 30578; Wed Dec  2 20:21:51 UTC 2026
