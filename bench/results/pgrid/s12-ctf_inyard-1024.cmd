commit 48ea1c1 load 1.14 1.26 1.33
build/cli/rtt bench ~/.cache/rtt-data/maps/ctf_inyard.bsp --views bench/views.json --size 1024  --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
load after 1.24 1.27 1.33
