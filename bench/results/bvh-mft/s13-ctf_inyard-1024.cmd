# commit c8fd8a3, Sat Dec  5 00:49:23 UTC 2026, load 1.44 1.52 1.17
build/cli/rtt bench ~/.cache/rtt-data/maps/ctf_inyard.bsp --views bench/views.json --size 1024 --accel bvh --only primary,build --frames 5 --threads 1,2 --json > bench/results/bvh-mft/s13-ctf_inyard-1024.json
