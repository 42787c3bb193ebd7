commit 48ea1c1 load 1.32 1.28 1.33
build/cli/rtt bench ~/.cache/rtt-data/maps/czest3ctf.bsp --views bench/views.json --size 1920 --height 1200 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
load after 1.18 1.25 1.32
