rtt bench /root/.cache/rtt-data/maps/oa_dm4.bsp --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
# binary: branch pghard at ed09115 (its shadow path is f79bb20's); niced 19; loadavg before: 7.26 6.16 4.10 8/114 17991
# exit 0; loadavg after: 8.72 6.67 4.36 10/128 21519; Wed Dec  2 10:01:37 UTC 2026
