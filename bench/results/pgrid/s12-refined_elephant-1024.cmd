commit 48ea1c1 load 1.20 1.29 1.35
build/cli/rtt bench ~/.cache/rtt-data/meshes/refined_elephant.off --views bench/views.json --size 1024  --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
load after 1.17 1.28 1.34
