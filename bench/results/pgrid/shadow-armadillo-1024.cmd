rtt bench /root/.cache/rtt-data/meshes/armadillo.off --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
# binary: branch pghard at ed09115 (its shadow path is f79bb20's); niced 19; loadavg before: 8.72 6.67 4.36 11/128 21526
# exit 0; loadavg after: 10.37 7.31 4.66 10/136 24279; Wed Dec  2 10:02:12 UTC 2026
