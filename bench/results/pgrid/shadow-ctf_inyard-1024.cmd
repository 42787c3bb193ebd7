rtt bench /root/.cache/rtt-data/maps/ctf_inyard.bsp --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
# binary: branch pghard at ed09115 (its shadow path is f79bb20's); niced 19; loadavg before: 10.43 7.58 4.82 12/142 27025
# exit 0; loadavg after: 12.71 8.78 5.42 12/145 30560; Wed Dec  2 10:03:41 UTC 2026
