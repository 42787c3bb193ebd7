commit c56b7d9 load 1.53 1.54 1.29
build/cli/rtt bench ~/.cache/rtt-data/maps/ctf_inyard.bsp --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
load after 1.59 1.55 1.30
