rtt bench /root/.cache/rtt-data/maps/oa_dm4.bsp --views bench/views.json --size 1024 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
# binary: branch pghard at f79bb20; niced 19; loadavg before: 12.67 9.76 6.10 14/141 6213
# exit 0; loadavg after: 15.42 11.03 6.75 16/145 11147; Wed Dec  2 10:06:09 UTC 2026
