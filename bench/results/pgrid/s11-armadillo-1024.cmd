commit acecdfa load 1.32 1.47 1.30
build/cli/rtt bench ~/.cache/rtt-data/meshes/armadillo.off --views bench/views.json --size 1024 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
load after 1.34 1.47 1.30
