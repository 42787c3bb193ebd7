commit acecdfa load 1.57 1.55 1.29
build/cli/rtt bench ~/.cache/rtt-data/maps/oa_dm4.bsp --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
load after 1.53 1.54 1.29
