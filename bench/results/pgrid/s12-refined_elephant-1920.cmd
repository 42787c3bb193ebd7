commit 48ea1c1 load 1.17 1.28 1.34
build/cli/rtt bench ~/.cache/rtt-data/meshes/refined_elephant.off --views bench/views.json --size 1920 --height 1200 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
load after 1.18 1.28 1.34
