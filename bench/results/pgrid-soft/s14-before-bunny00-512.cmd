# d4052c1 (the build before the column scan), Sun Dec  6 07:22:36 UTC 2026, load 0.78 2.05 2.40
/tmp/hack/head/cli/rtt bench ~/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --accel pgrid --only soft --size 512 --threads 1,2 --frames 3 --warmup 1 --json > bench/results/pgrid-soft/s14-before-bunny00-512.json
