rtt bench ~/.cache/rtt-data/meshes/armadillo.off --views bench/views.json --size 1024 --accel pgrid --only shadow,build --no-embree --frames 5 --threads 1,2 --pgrid-light-res 50,100,200,400,800 --json
# binary: branch pghard, an uncommitted state on the way to ed09115 (same grids; before the counting and placing loops were merged into band_pass and the shadow kernel moved onto bvh_simd.h; every row names its res); niced 19; loadavg before: 6.38 4.32 2.44 8/113 14022
# loadavg after: 6.63 4.51 2.55 7/123 15025
