commit acecdfa load 1.47 1.53 1.30
build/cli/rtt bench ~/.cache/rtt-data/maps/czest3ctf.bsp --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
load after 1.46 1.52 1.31
