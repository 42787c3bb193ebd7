commit c56b7d9 load 1.23 1.47 1.29
build/cli/rtt bench ~/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --size 1024 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
load after 1.35 1.49 1.30
