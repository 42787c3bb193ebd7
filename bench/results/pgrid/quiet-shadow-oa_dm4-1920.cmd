rtt bench /root/.cache/rtt-data/maps/oa_dm4.bsp --views bench/views.json --size 1920 --height 1200 --only shadow,build --frames 5 --threads 1,2 --json
# binary: main at a49975e; loadavg before: 1.33 1.34 1.29 1/79 30619
# exit 0; loadavg after: 1.77 1.41 1.31 3/83 30633; Wed Dec  2 20:24:01 UTC 2026
