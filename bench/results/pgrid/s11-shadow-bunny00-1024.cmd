commit acecdfa load 2.12 1.61 1.30
build/cli/rtt bench ~/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
load after 1.95 1.60 1.30
