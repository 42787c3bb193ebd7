rtt bench /root/.cache/rtt-data/maps/ctf_inyard.bsp --views bench/views.json --size 1920 --height 1200 --only shadow,build --frames 5 --threads 1,2 --json
# binary: main at d181d69; loadavg before: 1.37 1.98 1.93 1/74 23455
# exit 0; loadavg after: 1.37 1.81 1.87 1/79 23541; Wed Dec  2 19:32:54 UTC 2026
