rtt bench /root/.cache/rtt-data/maps/ctf_inyard.bsp --views bench/views.json --size 1024 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
# binary: branch pghard at f79bb20; niced 19; loadavg before: 14.82 11.66 7.23 16/154 19015
# exit 0; loadavg after: 15.60 12.40 7.72 15/139 23783; Wed Dec  2 10:08:02 UTC 2026
