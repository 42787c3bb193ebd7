rtt bench /root/.cache/rtt-data/maps/czest3ctf.bsp --views bench/views.json --size 1920 --height 1200 --only shadow,build --frames 5 --threads 1,2 --json
# binary: main at d181d69; loadavg before: 1.37 1.81 1.87 1/79 23545
# exit 0; loadavg after: 1.26 1.65 1.80 1/79 23568; Wed Dec  2 19:34:33 UTC 2026
