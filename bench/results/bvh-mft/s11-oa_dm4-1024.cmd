commit 4ca41b2 load 0.28 1.22 1.76
build/cli/rtt bench ~/.cache/rtt-data/maps/oa_dm4.bsp --views bench/views.json --size 1024 --accel bvh --only primary,build --frames 5 --threads 1,2 --json
load after 0.51 1.22 1.75
