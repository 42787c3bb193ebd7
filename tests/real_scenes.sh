#!/usr/bin/env bash
# rtt on the real data of the Debian packages (fetched by the fetch_data
# fixture into ${RTT_DATA_DIR:-~/.cache/rtt-data}): `rtt info` and a small
# render of a Quake III map (Bezier patches included) and of an OFF mesh,
# with both engines; the two images must agree (rtt compare).
set -euo pipefail
rtt="$1"
data="${RTT_DATA_DIR:-$HOME/.cache/rtt-data}"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

for scene in "$data/maps/oa_dm4.bsp" "$data/meshes/bunny00.off"; do
    [ -s "$scene" ] || { echo "real_scenes: $scene is missing (run bench/fetch-scenes.sh)"; exit 1; }
    name=$(basename "$scene")
    "$rtt" info "$scene" | tee "$work/$name.info"
    grep -Eq "triangles +[1-9]" "$work/$name.info" || { echo "real_scenes: $name: no triangles reported"; exit 1; }
    for engine in reference optimized; do
        "$rtt" render "$scene" --engine "$engine" --width 96 --height 96 -o "$work/$name.$engine.exr"
    done
    # the engines differ only where a ray grazes an edge: a few pixels at most
    "$rtt" compare "$work/$name.reference.exr" "$work/$name.optimized.exr" --max-share 0.01
done
echo "real_scenes: ok"
