# run from build/ at commit 4e60464
nice -n 19 ./cli/rtt bench ~/.cache/rtt-data/meshes/bunny00.off --view ../bench/views.json --lights view --only soft,build --size 1024 --threads 1,2 --frames 3 --warmup 1 --json
# load before and after:
5.21 5.45 3.61 6/102 4272
15.95 14.61 9.76 16/156 14637
