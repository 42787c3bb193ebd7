# commit fb8b2d5, Sun Dec  6 06:43:01 UTC 2026, load 0.89 1.16 1.18
build/cli/rtt bench ~/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --size 1024 --accel pgrid --only primary,shadow,build --frames 5 --threads 1,2 --json > bench/results/pgrid/s14-bunny00-1024.json
# load after: 1.16 1.21 1.19
