# commit 0ed590f, Sun Dec  6 06:25:34 UTC 2026, load 0.23 0.85 1.18
build/cli/rtt bench ~/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --size 1024 --accel bvh --only primary,soft,build --frames 5 --threads 1,2 --json > bench/results/bvh-mft/s14-bunny00-1024.json
# load after: 1.20 1.01 1.18
