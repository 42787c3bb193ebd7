commit acecdfa load 1.35 1.49 1.30
build/cli/rtt bench ~/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --size 1024 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
load after 1.38 1.49 1.30
