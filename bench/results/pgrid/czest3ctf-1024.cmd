rtt bench /root/.cache/rtt-data/maps/czest3ctf.bsp --views bench/views.json --size 1024 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
# binary: branch pghard at f79bb20; niced 19; loadavg before: 15.60 12.40 7.72 15/139 23793
# exit 0; loadavg after: 15.53 13.13 8.37 15/139 32413; Wed Dec  2 10:09:23 UTC 2026
