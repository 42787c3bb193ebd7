commit c56b7d9 load 1.33 1.44 1.30
build/cli/rtt bench ~/.cache/rtt-data/maps/czest3ctf.bsp --views bench/views.json --size 1024 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
load after 1.23 1.41 1.29
