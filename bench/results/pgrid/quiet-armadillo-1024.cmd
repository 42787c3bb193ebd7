rtt bench /root/.cache/rtt-data/meshes/armadillo.off --views bench/views.json --size 1024 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
# binary: main at a49975e; loadavg before: 1.32 1.27 1.26 1/80 30372
# exit 0; loadavg after: 1.29 1.27 1.26 2/80 30388; Wed Dec  2 20:13:41 UTC 2026
