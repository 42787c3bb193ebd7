build/cli/rtt bench ~/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json  # commit 211f70b, load before: 8.62 11.06 10.84
load after: 9.66 10.76 10.75
