#!/usr/bin/env bash
# What textures cost on the bench scenes: for each cached Quake III map, the
# same binary renders it (the map's own camera and lights, hard shadows,
# 1 thread) textured and untextured (RTT_TEXTURE_PATH pointing nowhere, so
# the map keeps one grey material), ROUNDS times interleaved; the table gives
# the best render time (--stats) and the best whole run (load, build, render,
# PNG write) of each, and the texture memory `rtt info` reports.  With
# BASE=path/to/an/older/rtt, the meshes (no textures) are also rendered by
# both binaries, to show that an untextured scene pays nothing.
#
# Usage: bench/textures-cost.sh [path/to/rtt] [--size N] [--rounds N]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
rtt="$root/build/cli/rtt"
if [[ $# -gt 0 && $1 != --* ]]; then rtt=$1; shift; fi
size=512 rounds=5
while [[ $# -gt 0 ]]; do
    case $1 in
    --size) size=$2 ;; --rounds) rounds=$2 ;;
    *) echo "textures-cost: unknown option $1" >&2; exit 2 ;;
    esac
    shift 2
done
data=$(bash "$root/bench/fetch-scenes.sh")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# one run: prints "render_seconds wall_seconds"
run() { # binary scene [env...]
    local binary=$1 scene=$2; shift 2
    local start end render
    start=$(date +%s.%N)
    render=$(env "$@" "$binary" render "$scene" --width "$size" --height "$size" --threads 1 --shadows hard --stats \
        -o "$work/out.png" 2>/dev/null | sed -n 's/^time: total \([0-9.]*\) s.*/\1/p')
    end=$(date +%s.%N)
    echo "$render $(echo "$end - $start" | bc)"
}

best() { sort -g | head -n 1; }

echo "| scene | textures | texture memory | render, untextured | render, textured | textured / untextured | whole run, untextured | whole run, textured |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|"
for map in oa_dm4 ctf_inyard czest3ctf; do
    scene="$data/maps/$map.bsp"
    : >"$work/plain" && : >"$work/textured"
    for _ in $(seq "$rounds"); do
        run "$rtt" "$scene" RTT_TEXTURE_PATH=/nonexistent >>"$work/plain"
        run "$rtt" "$scene" >>"$work/textured"
    done
    info=$("$rtt" info "$scene" 2>/dev/null | sed -n 's/^  textures    \([0-9]*\), \([0-9.]*\) MiB.*/\1 \2/p')
    p_render=$(cut -d' ' -f1 "$work/plain" | best) t_render=$(cut -d' ' -f1 "$work/textured" | best)
    p_wall=$(cut -d' ' -f2 "$work/plain" | best) t_wall=$(cut -d' ' -f2 "$work/textured" | best)
    printf '| %s | %s | %s MiB | %.3f s | %.3f s | %.3f | %.3f s | %.3f s |\n' "$map" "${info%% *}" "${info##* }" \
        "$p_render" "$t_render" "$(echo "$t_render / $p_render" | bc -l)" "$p_wall" "$t_wall"
done
if [[ -n "${BASE:-}" ]]; then
    echo
    echo "| mesh (no textures) | render, base | render, this binary | this / base |"
    echo "|---|---:|---:|---:|"
    for mesh in bunny00 armadillo refined_elephant; do
        scene="$data/meshes/$mesh.off"
        : >"$work/base" && : >"$work/this"
        for _ in $(seq "$rounds"); do
            run "$BASE" "$scene" >>"$work/base"
            run "$rtt" "$scene" >>"$work/this"
        done
        b=$(cut -d' ' -f1 "$work/base" | best) t=$(cut -d' ' -f1 "$work/this" | best)
        printf '| %s | %.3f s | %.3f s | %.3f |\n' "$mesh" "$b" "$t" "$(echo "$t / $b" | bc -l)"
    done
fi
