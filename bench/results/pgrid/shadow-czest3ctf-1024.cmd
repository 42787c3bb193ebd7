rtt bench /root/.cache/rtt-data/maps/czest3ctf.bsp --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
# binary: branch pghard at f79bb20; niced 19; loadavg before: 12.71 8.78 5.42 14/145 30565
# exit 0; loadavg after: 11.83 9.38 5.88 9/128 2818; Wed Dec  2 10:04:50 UTC 2026
