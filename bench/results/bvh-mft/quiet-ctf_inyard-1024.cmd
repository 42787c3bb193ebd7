rtt bench /root/.cache/rtt-data/maps/ctf_inyard.bsp --views bench/views.json --size 1024 --only primary,soft,build --accel bvh --frames 3 --warmup 0 --threads 1,2 --json
# binary: main at a49975e; loadavg before: 1.67 1.33 1.31 1/79 30247
# exit 0; loadavg after: 1.47 1.30 1.29 1/80 30271; Wed Dec  2 20:06:42 UTC 2026
