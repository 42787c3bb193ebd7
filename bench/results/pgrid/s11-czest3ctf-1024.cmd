commit acecdfa load 1.23 1.41 1.29
build/cli/rtt bench ~/.cache/rtt-data/maps/czest3ctf.bsp --views bench/views.json --size 1024 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
load after 1.16 1.38 1.28
