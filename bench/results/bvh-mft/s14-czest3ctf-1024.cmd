# commit fb8b2d5, Sun Dec  6 06:40:19 UTC 2026, load 1.40 1.25 1.21
build/cli/rtt bench ~/.cache/rtt-data/maps/czest3ctf.bsp --views bench/views.json --size 1024 --accel bvh --only primary,soft,build --frames 5 --threads 1,2 --json > bench/results/bvh-mft/s14-czest3ctf-1024.json
# load after: 1.47 1.29 1.22
