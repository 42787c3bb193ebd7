rtt bench /root/.cache/rtt-data/maps/ctf_inyard.bsp --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
# binary: branch pghard at 0d25d13; niced 19; loadavg before: 7.02 9.73 9.90 11/133 15951
# exit 0; loadavg after: 7.88 9.56 9.83 14/126 20474; Wed Dec  2 10:22:48 UTC 2026
