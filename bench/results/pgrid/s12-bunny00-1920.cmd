commit 48ea1c1 load 1.18 1.30 1.35
build/cli/rtt bench ~/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --size 1920 --height 1200 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
load after 1.24 1.31 1.35
