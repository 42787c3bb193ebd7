rtt bench /root/.cache/rtt-data/meshes/refined_elephant.off --views bench/views.json --size 1024 --accel pgrid --only primary,build --frames 5 --threads 1,2 --json
# binary: branch pghard at f79bb20; niced 19; loadavg before: 15.16 11.39 7.00 14/144 14816
# exit 0; loadavg after: 14.82 11.66 7.23 14/155 19009; Wed Dec  2 10:07:09 UTC 2026
