commit dae789a load 0.88 1.21 1.12
build/cli/rtt bench ~/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
load after 0.98 1.22 1.13
