rtt bench /root/.cache/rtt-data/maps/oa_dm4.bsp --views bench/views.json --size 1920 --height 1200 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
# binary: branch pghard at f79bb20; niced 19; loadavg before: 15.54 14.77 10.14 15/144 18492
# exit 0; loadavg after: 15.00 14.73 10.65 16/147 23965; Wed Dec  2 10:15:09 UTC 2026
