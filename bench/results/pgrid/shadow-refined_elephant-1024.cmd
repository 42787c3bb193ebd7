rtt bench /root/.cache/rtt-data/meshes/refined_elephant.off --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
# binary: branch pghard at ed09115 (its shadow path is f79bb20's); niced 19; loadavg before: 10.37 7.31 4.66 10/137 24286
# exit 0; loadavg after: 10.43 7.58 4.82 11/142 27019; Wed Dec  2 10:02:37 UTC 2026
