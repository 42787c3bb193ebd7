rtt bench /root/.cache/rtt-data/maps/czest3ctf.bsp --views bench/views.json --size 1920 --height 1200 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
# binary: main at d181d69; loadavg before: 1.26 1.51 1.73 1/79 23611
# exit 0; loadavg after: 1.12 1.39 1.66 1/79 23637; Wed Dec  2 19:38:15 UTC 2026
