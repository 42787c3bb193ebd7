commit c56b7d9 load 1.34 1.47 1.30
build/cli/rtt bench ~/.cache/rtt-data/meshes/refined_elephant.off --views bench/views.json --size 1024 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
load after 1.29 1.45 1.30
