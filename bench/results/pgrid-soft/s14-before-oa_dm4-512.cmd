# d4052c1 (the build before the column scan), Sun Dec  6 07:23:27 UTC 2026, load 0.99 1.90 2.33
/tmp/hack/head/cli/rtt bench ~/.cache/rtt-data/maps/oa_dm4.bsp --views bench/views.json --accel pgrid --only soft --size 512 --threads 1,2 --frames 3 --warmup 1 --json > bench/results/pgrid-soft/s14-before-oa_dm4-512.json
