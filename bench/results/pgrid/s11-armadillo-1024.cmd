commit 043722f load 1.82 1.70 1.17
build/cli/rtt bench ~/.cache/rtt-data/meshes/armadillo.off --views bench/views.json --size 1024 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
load after 1.69 1.68 1.17
