# commit fb8b2d5, Sun Dec  6 06:46:17 UTC 2026, load 1.11 1.17 1.18
build/cli/rtt bench ~/.cache/rtt-data/maps/czest3ctf.bsp --views bench/views.json --size 1024 --accel pgrid --only primary,shadow,build --frames 5 --threads 1,2 --json > bench/results/pgrid/s14-czest3ctf-1024.json
# load after: 1.22 1.18 1.18
