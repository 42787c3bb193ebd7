# commit 0ed590f, Sun Dec  6 06:30:40 UTC 2026, load 1.15 1.06 1.18
build/cli/rtt bench ~/.cache/rtt-data/meshes/refined_elephant.off --views bench/views.json --size 1024 --accel bvh --only primary,soft,build --frames 5 --threads 1,2 --json > bench/results/bvh-mft/s14-refined_elephant-1024.json
# load after: 1.29 1.11 1.18
