rtt bench /root/.cache/rtt-data/maps/ctf_inyard.bsp --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
# binary: main at a49975e; loadavg before: 1.39 1.30 1.28 1/79 30496
# exit 0; loadavg after: 1.39 1.32 1.28 1/79 30502; Wed Dec  2 20:18:01 UTC 2026
