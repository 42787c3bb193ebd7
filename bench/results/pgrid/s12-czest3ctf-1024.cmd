commit 48ea1c1 load 1.20 1.25 1.32
build/cli/rtt bench ~/.cache/rtt-data/maps/czest3ctf.bsp --views bench/views.json --size 1024  --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
load after 1.32 1.28 1.33
