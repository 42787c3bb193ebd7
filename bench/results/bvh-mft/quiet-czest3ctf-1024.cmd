rtt bench /root/.cache/rtt-data/maps/czest3ctf.bsp --views bench/views.json --size 1024 --only primary,soft,build --accel bvh --frames 3 --warmup 0 --threads 1,2 --json
# binary: main at a49975e; loadavg before: 1.47 1.30 1.29 1/80 30275
# exit 0; loadavg after: 1.58 1.30 1.27 1/80 30339; Wed Dec  2 20:12:37 UTC 2026
