# bcb1c1a (build), Sun Dec  6 07:22:58 UTC 2026, load 0.86 1.97 2.36
build/cli/rtt bench ~/.cache/rtt-data/maps/oa_dm4.bsp --views bench/views.json --accel pgrid --only soft --size 512 --threads 1,2 --frames 3 --warmup 1 --json > bench/results/pgrid-soft/s14-oa_dm4-512.json
