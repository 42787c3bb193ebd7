commit 043722f load 1.64 1.67 1.17
build/cli/rtt bench ~/.cache/rtt-data/maps/oa_dm4.bsp --views bench/views.json --size 1024 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
load after 1.50 1.63 1.17
