rtt bench /root/.cache/rtt-data/meshes/armadillo.off --views bench/views.json --size 1024 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
# binary: branch pghard at f79bb20; niced 19; loadavg before: 15.42 11.03 6.75 17/142 11153
# exit 0; loadavg after: 15.16 11.39 7.00 15/143 14810; Wed Dec  2 10:06:42 UTC 2026
