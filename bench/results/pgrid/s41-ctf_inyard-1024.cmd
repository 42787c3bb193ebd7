build/cli/rtt bench ~/.cache/rtt-data/maps/ctf_inyard.bsp --views bench/views.json --size 1024 --accel pgrid --only primary,shadow,build --frames 5 --threads 1,2 --json
