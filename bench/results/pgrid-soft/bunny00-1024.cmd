# run from build/ at commit 4ef809b
nice -n 19 ./cli/rtt bench ~/.cache/rtt-data/meshes/bunny00.off --view ../bench/views.json --lights view --only soft,build --size 1024 --threads 1,2 --frames 3 --warmup 1 --json
# load before: 3.76 6.19 8.20 8/130 6095
# load after: 5.42 6.00 7.88 5/114 13277
