rtt bench /root/.cache/rtt-data/maps/oa_dm4.bsp --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
# binary: branch pghard at 0d25d13; niced 19; loadavg before: 7.88 9.56 9.83 14/128 20478
# exit 0; loadavg after: 8.38 9.48 9.79 9/117 21664; Wed Dec  2 10:23:25 UTC 2026
