commit 48ea1c1 load 1.24 1.31 1.35
build/cli/rtt bench ~/.cache/rtt-data/meshes/armadillo.off --views bench/views.json --size 1024  --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
load after 1.29 1.32 1.35
