commit c56b7d9 load 1.57 1.55 1.31
build/cli/rtt bench ~/.cache/rtt-data/maps/czest3ctf.bsp --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
load after 1.47 1.53 1.30
