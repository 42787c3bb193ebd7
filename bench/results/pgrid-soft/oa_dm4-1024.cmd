# run from build/ at commit 4ef809b
nice -n 19 ./cli/rtt bench ~/.cache/rtt-data/maps/oa_dm4.bsp --view ../bench/views.json --lights view --only soft,build --size 1024 --threads 1,2 --frames 3 --warmup 1 --json
# load before: 5.42 6.00 7.88 6/114 13287
# load after: 4.52 5.22 7.09 4/100 31772
