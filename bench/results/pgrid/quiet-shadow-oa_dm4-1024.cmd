rtt bench /root/.cache/rtt-data/maps/oa_dm4.bsp --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
# binary: main at a49975e; loadavg before: 1.32 1.27 1.27 1/80 30449
# exit 0; loadavg after: 1.39 1.30 1.28 1/80 30473; Wed Dec  2 20:16:15 UTC 2026
