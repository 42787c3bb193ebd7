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
# Every cached map with no scene file: the camera is the map's own
# (intermission point or spawn point), the lights are the map's own (light
# entities or its light grid), and the camera is inside the level: at least
# 90% of its primary rays hit (from outside, most miss), and a render works.
for map in "$data"/maps/*.bsp; do
    name=$(basename "$map" .bsp)
    "$rtt" info "$map" --engine optimized >"$work/$name.info"
    grep -Eq "camera .*\(the map's (info_player_intermission|first spawn point)\)" "$work/$name.info" ||
        { echo "real_scenes: $name: not the map's own camera"; grep camera "$work/$name.info"; exit 1; }
    grep -Eq "lights +[1-9][0-9]* .*from the (map's light entities|brightest points of the map's light grid)" \
        "$work/$name.info" || { echo "real_scenes: $name: not lit by its own lights"; grep lights "$work/$name.info"; exit 1; }
    "$rtt" rays "$map" --kind primary -n 4096 -o "$work/$name.rays" >/dev/null
    "$rtt" trace "$map" --rays "$work/$name.rays" -o "$work/$name.hits" >/dev/null
    read -r total missed < <(od -An -tu4 -w16 -v "$work/$name.hits" |
        awk '{ n++; if ($4 == 4294967295) m++ } END { print n, m + 0 }')
    echo "real_scenes: $name: $missed of $total primary rays miss"
    [ "$total" -gt 0 ] && [ $((missed * 10)) -le "$total" ] ||
        { echo "real_scenes: $name: the camera sees out of the level"; exit 1; }
    "$rtt" render "$map" --width 64 --height 48 -o "$work/$name.png"
done
echo "real_scenes: ok"
