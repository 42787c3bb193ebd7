commit acecdfa load 1.27 1.44 1.29
build/cli/rtt bench ~/.cache/rtt-data/maps/oa_dm4.bsp --views bench/views.json --size 1024 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
load after 1.44 1.47 1.31
