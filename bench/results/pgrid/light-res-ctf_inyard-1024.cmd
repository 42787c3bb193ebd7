rtt bench ~/.cache/rtt-data/maps/ctf_inyard.bsp --views bench/views.json --size 1024 --accel pgrid --only shadow,build --no-embree --frames 5 --threads 1,2 --pgrid-light-res 50,100,200,400,800 --json
# binary: branch pghard, an uncommitted state on the way to ed09115 (same grids; before the counting and placing loops were merged into band_pass and the shadow kernel moved onto bvh_simd.h; every row names its res); niced 19; loadavg before: 7.02 4.73 2.66 8/110 15603
# loadavg after: 6.22 4.83 2.78 5/100 16628
