commit acecdfa load 1.80 1.58 1.29
build/cli/rtt bench ~/.cache/rtt-data/meshes/armadillo.off --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
load after 1.68 1.56 1.29
