rtt bench /root/.cache/rtt-data/maps/ctf_inyard.bsp --views bench/views.json --size 1024 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
# binary: main at a49975e; loadavg before: 1.39 1.30 1.28 1/80 30477
# exit 0; loadavg after: 1.39 1.30 1.28 5/79 30493; Wed Dec  2 20:16:59 UTC 2026
