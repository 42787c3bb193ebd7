# commit 0ed590f, Sun Dec  6 06:32:57 UTC 2026, load 1.29 1.11 1.18
build/cli/rtt bench ~/.cache/rtt-data/maps/oa_dm4.bsp --views bench/views.json --size 1024 --accel bvh --only primary,soft,build --frames 5 --threads 1,2 --json > bench/results/bvh-mft/s14-oa_dm4-1024.json
# load after: 1.58 1.24 1.20
