# commit 4eb4235, Sat Dec  5 00:48:27 UTC 2026, load 1.88 1.59 1.17
build/cli/rtt bench ~/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --size 1024 --accel bvh --only primary,build --frames 5 --threads 1,2 --json > bench/results/bvh-mft/s13-bunny00-1024.json
