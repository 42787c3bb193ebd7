rtt bench /root/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --size 1024 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
# binary: branch pghard at f79bb20; niced 19; loadavg before: 11.83 9.38 5.88 12/129 2824
# exit 0; loadavg after: 12.67 9.76 6.10 14/144 6208; Wed Dec  2 10:05:19 UTC 2026
