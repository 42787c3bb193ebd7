rtt bench /root/.cache/rtt-data/maps/oa_dm4.bsp --views bench/views.json --size 1920 --height 1200 --only shadow,build --frames 5 --threads 1,2 --json
# binary: branch pghard at f79bb20; niced 19; loadavg before: 16.41 14.50 9.53 17/148 11313
# exit 0; loadavg after: 15.54 14.77 10.14 15/144 18490; Wed Dec  2 10:13:17 UTC 2026
