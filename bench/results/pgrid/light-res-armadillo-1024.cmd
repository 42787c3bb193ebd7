rtt bench ~/.cache/rtt-data/meshes/armadillo.off --views bench/views.json --size 1024 --accel pgrid --only shadow,build --no-embree --frames 5 --threads 1,2 --pgrid-light-res 50,100,200,400,800 --json
# binary: branch pghard at 7d5e45f + uncommitted light-build changes; loadavg before: 6.38 4.32 2.44 8/113 14022
# loadavg after: 6.63 4.51 2.55 7/123 15025
