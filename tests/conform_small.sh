#!/usr/bin/env bash
# Hit-by-hit conformance on every small scene in scenes/ (every ray set:
# primary, shadow, random, extreme; every optimized traversal mode and
# Embree against the reference).  Each run must exit 0: the thresholds are
# in conformance/README.md.  4096 rays per set keeps the whole test to
# about 15 s on two cores; demo.json (43k triangles) is left to the full
# suite (`rtt conform scenes/demo.json`).
set -u
rtt="$1"
src="$2"
failures=0
count=0
for scene in "$src"/scenes/*.json; do
    case "$(basename "$scene")" in demo.json) continue ;; esac
    count=$((count + 1))
    if ! out=$("$rtt" conform "$scene" --rays all --max-rays 4096 2>&1); then
        echo "FAIL: rtt conform $scene"
        echo "$out" | sed 's/^/    /'
        failures=$((failures + 1))
    fi
done
if [ "$count" -eq 0 ]; then
    echo "FAIL: no scenes in $src/scenes"
    exit 1
fi
echo "conform_small: $count scenes, $failures failed"
[ "$failures" -eq 0 ]
