commit dae789a load 0.98 1.22 1.13
build/cli/rtt bench ~/.cache/rtt-data/meshes/armadillo.off --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
load after 1.06 1.23 1.13
