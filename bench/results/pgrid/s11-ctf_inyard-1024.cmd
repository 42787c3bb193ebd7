commit acecdfa load 1.42 1.46 1.31
build/cli/rtt bench ~/.cache/rtt-data/maps/ctf_inyard.bsp --views bench/views.json --size 1024 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
load after 1.33 1.44 1.30
