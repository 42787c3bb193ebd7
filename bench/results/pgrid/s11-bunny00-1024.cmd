commit 043722f load 1.88 1.71 1.17
build/cli/rtt bench ~/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --size 1024 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
load after 1.82 1.70 1.17
