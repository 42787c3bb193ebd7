# bcb1c1a (build), Sun Dec  6 07:22:17 UTC 2026, load 0.70 2.13 2.43
build/cli/rtt bench ~/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --accel pgrid --only soft --size 512 --threads 1,2 --frames 3 --warmup 1 --json > bench/results/pgrid-soft/s14-bunny00-512.json
