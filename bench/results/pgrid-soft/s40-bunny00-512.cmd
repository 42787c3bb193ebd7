build/cli/rtt bench ~/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --accel pgrid --only soft --size 512 --threads 1,2 --frames 3 --warmup 1 --json  # at 649aa5d, 2026-12-08T03:57:09Z
