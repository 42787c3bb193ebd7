rtt bench /root/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --size 1920 --height 1200 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
# binary: branch pghard at f79bb20; niced 19; loadavg before: 16.85 13.95 8.95 19/164 5166
# exit 0; loadavg after: 16.54 14.49 9.50 16/148 11307; Wed Dec  2 10:11:35 UTC 2026
