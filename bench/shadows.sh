#!/usr/bin/env bash
# The soft-shadow trade (Thesis Table 4.6 and Table 5.1), measured.
#
#   bench/shadows.sh [RTT]        RTT: the rtt binary (default build/cli/rtt)
#
# For each scene — scenes/shadow_*.json, scenes/light_quad.json (no
# edgewidth rows: it refuses quad lights), and the benchmark scenes of
# ${RTT_DATA_DIR:-~/.cache/rtt-data} named in bench/views.json when both
# exist — renders the truth with the reference renderer at multi:256, then
# every method with the optimized renderer, and reports the median render
# time over RTT_SHADOW_RUNS runs (default 3; `rtt render --stats` "time:
# total", which excludes loading and the tree build), rays per second, and
# the error against the truth (`rtt compare --json`: RMSE, max, share of
# pixels off by more than 1/255).  Methods: hard; edgewidth at three radii
# (RTT_SHADOW_RADII, fractions of the light-to-point distance) without and
# with --edge-leak-fix; multi:4, 8, 16, 32; cone:16; pyramid:16; and, with
# the reference renderer (the image a frusta kernel must reproduce),
# interleaved:4, 8, 16, 32 with and without the discontinuity filter
# (labels "interleaved:N ref", "interleaved:N:nofilter ref"; one run each:
# they are there for their error, the reference's time is the oracle's);
# and frusta:4, 8, 16, 32 with and without the filter and with the
# refining second pass (:refine; the optimized renderer with --accel bvh:
# the same samples as multi-frusta).  Then cone:16
# against pyramid:16 with the light radius set to 1 and to 2 (Table 4.6).
# Every row names its engine.
#
# Output (bench/results/, or RTT_SHADOW_RESULTS): shadows.json (every
# row), shadows.md (the tables, Table 5.1 as ratios to hard shadows) and
# shadows.png (time against RMSE, gnuplot).  Threads: RTT_SHADOW_THREADS
# (default 1: the figures compare methods, not machines).  RTT_SHADOW_NOTE:
# a sentence for the report's introduction (say when the machine was shared).
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
rtt=${1:-${RTT:-$root/build/cli/rtt}}
results=${RTT_SHADOW_RESULTS:-$here/results}
runs=${RTT_SHADOW_RUNS:-3}
threads=${RTT_SHADOW_THREADS:-1}
radii=${RTT_SHADOW_RADII:-0.02 0.05 0.1}
data=${RTT_DATA_DIR:-$HOME/.cache/rtt-data}
views=$here/views.json

[ -x "$rtt" ] || { echo "shadows.sh: no rtt binary at $rtt (build it, or pass its path)" >&2; exit 2; }
for tool in jq python3; do
    command -v "$tool" >/dev/null || { echo "shadows.sh: needs $tool" >&2; exit 2; }
done
mkdir -p "$results"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
rows=$work/rows.jsonl
: >"$rows"

# scene list: name<TAB>path
scenes=$work/scenes.tsv
: >"$scenes"
for s in "$root"/scenes/shadow_*.json "$root"/scenes/light_quad.json; do
    [ -e "$s" ] && printf '%s\t%s\n' "$(basename "$s" .json)" "$s" >>"$scenes"
done
# Benchmark scenes: a scene file wrapping the map or mesh with the view's
# camera and light (a sphere light: radius from the view, else 1% of the
# way from the light to the camera so that there is a penumbra at all).
if [ -f "$views" ] && [ -d "$data" ]; then
    for name in $(jq -r 'keys[] | select(startswith("_") | not)' "$views"); do
        file=$(find "$data" -name "$name.*" \( -name '*.bsp' -o -name '*.off' -o -name '*.obj' -o -name '*.ply' \) | head -n 1)
        [ -n "$file" ] || continue
        jq --arg file "$file" --arg name "$name" '.[$name] as $v | {
            camera: {eye: $v.camera.eye, look_at: $v.camera.look_at, up: ($v.camera.up // [0,0,1]),
                     fov: ($v.camera.fov // 60)},
            image: {width: (($v.size // [512,512])[0]), height: (($v.size // [512,512])[1])},
            lights: [{type: "sphere", position: $v.light.position, intensity: ($v.light.intensity // 1),
                      radius: (if ($v.light.radius // 0) > 0 then $v.light.radius else
                        ([range(0;3)] | map(($v.light.position[.] - $v.camera.eye[.]) | . * .) | add | sqrt * 0.01) end)}],
            meshes: [{file: $file}]}' "$views" >"$work/bench_$name.json"
        printf '%s\t%s\n' "$name" "$work/bench_$name.json" >>"$scenes"
    done
fi

median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }

# render NAME SCENE METHOD LEAKFIX LABEL [ENGINE]: median time, rays/s, error vs truth
render() {
    local name=$1 scene=$2 method=$3 fix=$4 label=$5 engine=${6:-optimized} extra=()
    [ "$fix" = 1 ] && extra=(--edge-leak-fix)
    case "$method" in frusta*) extra+=(--accel bvh) ;; esac # the soft-shadow frusta walk the BVH
    local image=$work/$name.$label.exr times=() rate=0 line n=$runs
    [ "$engine" = reference ] && n=1 # its rows are for the image; its time is the scalar oracle's
    for ((run = 0; run < n; run++)); do
        "$rtt" render "$scene" --engine "$engine" --shadows "$method" "${extra[@]}" --threads "$threads" \
            --stats -o "$image" >"$work/stats.txt"
        times+=("$(awk '/^time: total/ {print $3}' "$work/stats.txt")")
        rate=$(awk -F'; ' '/^rays:/ {split($2, r, " "); print r[1]}' "$work/stats.txt")
    done
    local time
    time=$(printf '%s\n' "${times[@]}" | median)
    "$rtt" compare "$image" "$work/$name.truth.exr" --json >"$work/compare.json"
    jq -c --arg scene "$name" --arg method "$method" --arg lab "$label" --argjson fix "$fix" \
        --argjson time "$time" --argjson rate "$rate" --argjson runs "$n" --arg engine "$engine" \
        '{scene: $scene, engine: $engine, method: $method, "label": $lab, leak_fix: ($fix == 1), seconds: $time,
          rays_per_second: $rate, runs: $runs} + .' "$work/compare.json" >>"$rows"
    printf '  %-26s %8.4f s  %10.3g rays/s  rmse %.5f\n' "$label" "$time" "$rate" \
        "$(jq .rmse "$work/compare.json")" >&2
}

while IFS=$'\t' read -r name scene; do
    echo "$name: truth (reference, multi:256)" >&2
    "$rtt" render "$scene" --engine reference --shadows multi:256 --threads 2 -o "$work/$name.truth.exr" >/dev/null
    render "$name" "$scene" hard 0 hard
    quad=$(jq '[.lights[]? | select(.type == "quad")] | length' "$scene")
    if [ "$quad" = 0 ]; then
        for r in $radii; do
            render "$name" "$scene" "edgewidth:$r" 0 "edgewidth:$r"
            render "$name" "$scene" "edgewidth:$r" 1 "edgewidth:$r+fix"
        done
    fi
    for n in 4 8 16 32; do render "$name" "$scene" "multi:$n" 0 "multi:$n"; done
    render "$name" "$scene" cone:16 0 cone:16
    render "$name" "$scene" pyramid:16 0 pyramid:16
    for n in 4 8 16 32; do
        render "$name" "$scene" "interleaved:$n" 0 "interleaved:$n ref" reference
        render "$name" "$scene" "interleaved:$n:nofilter" 0 "interleaved:$n:nofilter ref" reference
    done
    for n in 4 8 16 32; do
        render "$name" "$scene" "frusta:$n" 0 "frusta:$n"
        render "$name" "$scene" "frusta:$n:nofilter" 0 "frusta:$n:nofilter"
        render "$name" "$scene" "frusta:$n:refine" 0 "frusta:$n:refine"
    done
done <"$scenes"

# Table 4.6: cone:16 against pyramid:16 for light radii 1 and 2 (the test
# scenes only: their lights are plain JSON we can rewrite).
for radius in 1 2; do
    for s in "$root"/scenes/shadow_*.json; do
        [ -e "$s" ] || continue
        name=$(basename "$s" .json)@r$radius
        jq --argjson r "$radius" '.lights |= map(if .type == "sphere" then .radius = $r else . end)' "$s" \
            >"$work/$name.json"
        echo "$name: truth (reference, multi:256)" >&2
        "$rtt" render "$work/$name.json" --engine reference --shadows multi:256 --threads 2 \
            -o "$work/$name.truth.exr" >/dev/null
        render "$name" "$work/$name.json" cone:16 0 cone:16
        render "$name" "$work/$name.json" pyramid:16 0 pyramid:16
    done
done

python3 "$here/shadows_report.py" "$rows" "$results" "$threads" "$runs"
if command -v gnuplot >/dev/null; then
    (cd "$results" && gnuplot shadows.gp)
else
    echo "shadows.sh: gnuplot not found; no shadows.png" >&2
fi
echo "shadows.sh: wrote $results/shadows.json, shadows.md, shadows.png" >&2
