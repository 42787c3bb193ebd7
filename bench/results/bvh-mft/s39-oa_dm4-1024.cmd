build/cli/rtt bench ~/.cache/rtt-data/maps/oa_dm4.bsp --views bench/views.json --size 1024 --accel bvh --only primary,soft,build --frames 5 --threads 1,2 --json
