rtt bench /root/.cache/rtt-data/maps/czest3ctf.bsp --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
# binary: main at a49975e; loadavg before: 1.33 1.32 1.28 1/79 30543
# exit 0; loadavg after: 1.27 1.30 1.27 1/79 30549; Wed Dec  2 20:20:36 UTC 2026
