# commit fb8b2d5, Sun Dec  6 06:44:06 UTC 2026, load 1.14 1.20 1.19
build/cli/rtt bench ~/.cache/rtt-data/meshes/refined_elephant.off --views bench/views.json --size 1024 --accel pgrid --only primary,shadow,build --frames 5 --threads 1,2 --json > bench/results/pgrid/s14-refined_elephant-1024.json
# load after: 1.09 1.18 1.18
