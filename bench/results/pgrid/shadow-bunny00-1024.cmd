rtt bench /root/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
# binary: branch pghard at ed09115 (its shadow path is f79bb20's); niced 19; loadavg before: 6.96 5.99 3.98 11/124 15521
# exit 0; loadavg after: 7.26 6.16 4.10 8/111 17982; Wed Dec  2 10:00:57 UTC 2026
