rtt bench /root/.cache/rtt-data/maps/ctf_inyard.bsp --views bench/views.json --size 1920 --height 1200 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
# binary: main at d181d69; loadavg before: 1.26 1.57 1.77 1/79 23598
# exit 0; loadavg after: 1.26 1.51 1.73 1/79 23607; Wed Dec  2 19:36:30 UTC 2026
