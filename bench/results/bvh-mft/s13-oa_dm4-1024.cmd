# commit c8fd8a3, Sat Dec  5 00:49:03 UTC 2026, load 1.62 1.55 1.17
build/cli/rtt bench ~/.cache/rtt-data/maps/oa_dm4.bsp --views bench/views.json --size 1024 --accel bvh --only primary,build --frames 5 --threads 1,2 --json > bench/results/bvh-mft/s13-oa_dm4-1024.json
