build/cli/rtt bench ~/.cache/rtt-data/meshes/refined_elephant.off --views bench/views.json --size 1920 --height 1200 --accel pgrid --only primary,shadow,build --frames 5 --threads 1,2 --json
