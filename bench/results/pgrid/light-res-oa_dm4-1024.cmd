rtt bench ~/.cache/rtt-data/maps/oa_dm4.bsp --views bench/views.json --size 1024 --accel pgrid --only shadow,build --no-embree --frames 5 --threads 1,2 --pgrid-light-res 50,100,200,400,800 --json
# binary: branch pghard at 7d5e45f + uncommitted light-build changes; loadavg before: 4.81 3.82 2.22 8/127 12024
# loadavg after: 6.38 4.32 2.44 7/113 14017
