# commit fb8b2d5, Sun Dec  6 06:38:26 UTC 2026, load 1.62 1.26 1.21
build/cli/rtt bench ~/.cache/rtt-data/maps/ctf_inyard.bsp --views bench/views.json --size 1024 --accel bvh --only primary,soft,build --frames 5 --threads 1,2 --json > bench/results/bvh-mft/s14-ctf_inyard-1024.json
# load after: 1.40 1.25 1.21
