commit 48ea1c1 load 1.18 1.28 1.34
build/cli/rtt bench ~/.cache/rtt-data/maps/oa_dm4.bsp --views bench/views.json --size 1024  --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
load after 1.14 1.27 1.33
