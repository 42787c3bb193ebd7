build/cli/rtt bench ~/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --size 1024 --accel bvh --only primary,soft,build --frames 5 --threads 1,2 --json
