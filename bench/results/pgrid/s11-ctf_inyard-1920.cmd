commit acecdfa load 1.21 1.30 1.26
build/cli/rtt bench ~/.cache/rtt-data/maps/ctf_inyard.bsp --views bench/views.json --size 1920 --height 1200 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
load after 1.32 1.32 1.27
