# run from build/ at commit 4ef809b
nice -n 19 ./cli/rtt bench ~/.cache/rtt-data/maps/oa_dm4.bsp --view ../bench/views.json --lights view --only soft,build --size 512 --threads 1,2 --frames 3 --warmup 1 --json
# load before: 4.58 7.14 8.68 3/107 31888
# load after: 4.10 6.51 8.37 4/106 3269
