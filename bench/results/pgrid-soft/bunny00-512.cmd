# run from build/ at commit 4ef809b
nice -n 19 ./cli/rtt bench ~/.cache/rtt-data/meshes/bunny00.off --view ../bench/views.json --lights view --only soft,build --size 512 --threads 1,2 --frames 3 --warmup 1 --json
# load before: 5.07 7.45 8.82 6/112 31106
# load after: 4.58 7.14 8.68 3/107 31883
