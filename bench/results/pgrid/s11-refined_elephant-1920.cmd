commit acecdfa load 1.01 1.29 1.26
build/cli/rtt bench ~/.cache/rtt-data/meshes/refined_elephant.off --views bench/views.json --size 1920 --height 1200 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
load after 1.09 1.30 1.26
