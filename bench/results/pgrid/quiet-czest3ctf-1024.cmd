rtt bench /root/.cache/rtt-data/maps/czest3ctf.bsp --views bench/views.json --size 1024 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
# binary: main at a49975e; loadavg before: 1.39 1.32 1.28 1/79 30506
# exit 0; loadavg after: 1.33 1.32 1.28 1/79 30540; Wed Dec  2 20:19:19 UTC 2026
