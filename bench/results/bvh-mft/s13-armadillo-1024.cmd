# commit 4eb4235, Sat Dec  5 00:48:41 UTC 2026, load 1.77 1.58 1.17
build/cli/rtt bench ~/.cache/rtt-data/meshes/armadillo.off --views bench/views.json --size 1024 --accel bvh --only primary,build --frames 5 --threads 1,2 --json > bench/results/bvh-mft/s13-armadillo-1024.json
