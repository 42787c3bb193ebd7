rtt bench /root/.cache/rtt-data/maps/oa_dm4.bsp --views bench/views.json --size 1024 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
# binary: main at a49975e; loadavg before: 1.34 1.28 1.27 1/80 30430
# exit 0; loadavg after: 1.32 1.27 1.27 1/80 30446; Wed Dec  2 20:15:27 UTC 2026
