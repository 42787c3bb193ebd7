commit acecdfa load 1.59 1.55 1.30
build/cli/rtt bench ~/.cache/rtt-data/maps/ctf_inyard.bsp --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
load after 1.57 1.55 1.31
