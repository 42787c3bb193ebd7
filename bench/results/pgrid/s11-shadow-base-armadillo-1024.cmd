commit c56b7d9 load 1.95 1.60 1.30
build/cli/rtt bench ~/.cache/rtt-data/meshes/armadillo.off --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
load after 1.80 1.58 1.29
