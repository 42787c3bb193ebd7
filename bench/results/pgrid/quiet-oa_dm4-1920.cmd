rtt bench /root/.cache/rtt-data/maps/oa_dm4.bsp --views bench/views.json --size 1920 --height 1200 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
# binary: main at a49975e; loadavg before: 1.40 1.34 1.29 1/79 30582
# exit 0; loadavg after: 1.33 1.34 1.29 1/79 30616; Wed Dec  2 20:22:55 UTC 2026
