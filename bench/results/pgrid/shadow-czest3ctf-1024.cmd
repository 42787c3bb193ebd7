rtt bench /root/.cache/rtt-data/maps/czest3ctf.bsp --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
# binary: branch pghard at 0d25d13; niced 19; loadavg before: 6.38 10.18 10.05 6/112 13555
# exit 0; loadavg after: 7.02 9.73 9.90 12/133 15949; Wed Dec  2 10:21:58 UTC 2026
