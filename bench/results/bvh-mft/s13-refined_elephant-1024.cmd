# commit c8fd8a3, Sat Dec  5 00:48:52 UTC 2026, load 1.65 1.56 1.17
build/cli/rtt bench ~/.cache/rtt-data/meshes/refined_elephant.off --views bench/views.json --size 1024 --accel bvh --only primary,build --frames 5 --threads 1,2 --json > bench/results/bvh-mft/s13-refined_elephant-1024.json
