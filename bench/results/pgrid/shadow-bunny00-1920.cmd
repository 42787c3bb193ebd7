rtt bench /root/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --size 1920 --height 1200 --only shadow,build --frames 5 --threads 1,2 --json
# binary: branch pghard at f79bb20; niced 19; loadavg before: 15.53 13.13 8.37 15/140 32419
# exit 0; loadavg after: 16.85 13.95 8.95 17/163 5163; Wed Dec  2 10:10:24 UTC 2026
