rtt bench /root/.cache/rtt-data/maps/oa_dm4.bsp --views bench/views.json --size 1024 --only primary,soft,build --accel bvh --frames 3 --warmup 0 --threads 1,2 --json
# binary: main at a49975e; loadavg before: 1.27 1.20 1.30 1/80 30237
# exit 0; loadavg after: 1.67 1.33 1.31 1/79 30243; Wed Dec  2 20:01:59 UTC 2026
