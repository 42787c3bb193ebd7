commit acecdfa load 1.02 1.31 1.26
build/cli/rtt bench ~/.cache/rtt-data/meshes/armadillo.off --views bench/views.json --size 1920 --height 1200 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
load after 1.01 1.29 1.26
