commit c56b7d9 load 2.23 1.62 1.29
build/cli/rtt bench ~/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
load after 2.12 1.61 1.30
