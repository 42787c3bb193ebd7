# 914a274 (before the near-plane clipping and edge stepping), 22:2x-22:4x
build/cli/rtt bench ~/.cache/rtt-data/meshes/bunny00.off --views bench/views.json --size 1024 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
