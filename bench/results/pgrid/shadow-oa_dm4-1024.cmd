build/cli/rtt bench ~/.cache/rtt-data/maps/oa_dm4.bsp --views bench/views.json --size 1024 --only shadow,build --frames 5 --threads 1,2 --json  # commit 211f70b, load before: 9.66 10.76 10.75
load after: 9.84 10.51 10.66
