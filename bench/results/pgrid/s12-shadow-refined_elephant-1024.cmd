commit 5032da8 load 1.26 1.50 2.02
build/cli/rtt bench ~/.cache/rtt-data/meshes/refined_elephant.off --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json
load after 1.22 1.49 2.01
