#!/usr/bin/env bash
# The interactive frame rates of `rtt view` (the thesis' chapter 6, Table 6.2):
# every bench scene at 512x512 from its bench/views.json view, each traversal
# kernel the optimized engine offers with hard and edge-width shadows, on one
# thread and two, played headless under Xvfb (rtt view --script, `bench N`:
# N frames rendered and presented, the mean fps and Mrays/s).  Writes
# bench/results/viewer-fps.md (and .tsv).
#
# Usage: bench/viewer-fps.sh [--rtt PATH] [--scenes "oa_dm4 ..."] [--frames N]
#                            [--threads "1 2"] [--kernels "mft ..."] [--size N]
set -euo pipefail
src="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
rtt="${RTT:-$src/build/cli/rtt}"
scenes="oa_dm4 ctf_inyard czest3ctf bunny00 armadillo refined_elephant"
frames=10
threads="1 2"
kernels=""
size=512
command_line="bench/viewer-fps.sh $*"
while [[ $# -gt 0 ]]; do
    case "$1" in
        --rtt) rtt="$2"; shift 2 ;;
        --scenes) scenes="$2"; shift 2 ;;
        --frames) frames="$2"; shift 2 ;;
        --threads) threads="$2"; shift 2 ;;
        --kernels) kernels="$2"; shift 2 ;;
        --size) size="$2"; shift 2 ;;
        *) sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2 ;;
    esac
done
command -v xvfb-run >/dev/null || { echo "viewer-fps: xvfb-run missing (ci/install-deps.sh installs xvfb)" >&2; exit 1; }
data="$(bash "$src/bench/fetch-scenes.sh")"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
# every kernel the optimized engine offers, as the viewer's T key cycles them
if [[ -z "$kernels" ]]; then
    printf 'print-choices\n' >"$work/choices.txt"
    kernels="$(xvfb-run -a "$rtt" view "$src/scenes/demo.json" --width 16 --height 16 --script "$work/choices.txt" |
        sed -n 's/^traversals: //p')"
fi
[[ -n "$kernels" ]] || { echo "viewer-fps: no kernels offered" >&2; exit 1; }
scene_path() {
    if [[ -s "$data/maps/$1.bsp" ]]; then echo "$data/maps/$1.bsp"
    elif [[ -s "$data/meshes/$1.off" ]]; then echo "$data/meshes/$1.off"
    else echo "viewer-fps: no scene $1 in $data" >&2; return 1; fi
}
script="$work/script.txt"
: >"$script"
# the shadow methods of the thesis' garage benchmark: hard, and edge widths
# where the accel draws them (the BVH's renderer has hard and sampled ones only)
shadows_of() { case "$1" in bvh:*) echo hard ;; *) echo hard edgewidth ;; esac; }
for k in $kernels; do
    for s in $(shadows_of "$k"); do
        # hard first: every accel draws it, so the switch of traversal is never refused
        printf 'set shadows hard\nset traversal %s\nset shadows %s\nframes 2\nbench %s\n' "$k" "$s" "$frames" >>"$script"
    done
done
tsv="$src/bench/results/viewer-fps.tsv"
load_before="$(cut -d' ' -f1-3 /proc/loadavg)"
printf 'scene\tthreads\tkernel\tshadows\tfps\tmrays\trender_ms\tpresent_ms\n' >"$tsv.tmp"
for scene in $scenes; do
    path="$(scene_path "$scene")"
    for t in $threads; do
        # the view's own light, as rtt bench uses it
        xvfb-run -a -s "-screen 0 1280x1024x24" "$rtt" view "$path" --view "$src/bench/views.json:$scene" --lights view \
            --width "$size" --height "$size" --threads "$t" --tile 16 --spp 1 --script "$script" >"$work/out.txt"
        sed -n 's/^bench: [0-9]* frames, \([0-9.]*\) fps, \([0-9.]*\) Mrays\/s, \([a-z0-9]*\) \([a-z0-9-]*\)\/[a-z0-9]*, shadows \([a-z:0-9.]*\), .*, render \([0-9.]*\) ms, present \([0-9.]*\) ms$/\3:\4\t\5\t\1\t\2\t\6\t\7/p' \
            "$work/out.txt" | sed "s/^/$scene\t$t\t/" >>"$tsv.tmp"
    done
done
mv "$tsv.tmp" "$tsv"
load_after="$(cut -d' ' -f1-3 /proc/loadavg)"
md="$src/bench/results/viewer-fps.md"
{
    echo "# rtt view: interactive frame rates (${size}x${size})"
    echo
    echo "Made by \`$command_line\` on $(date -u +%Y-%m-%d), $(lscpu | sed -n 's/^Model name:[[:space:]]*//p' | head -n 1),"
    echo "$(nproc) cores; rtt view under Xvfb, each figure the mean of $frames frames rendered and presented"
    echo "(\`bench $frames\` in a view script) after 2 unmeasured ones; tile 16, the view of bench/views.json and its light (\`--lights view\`)."
    echo "Load average (1, 5, 15 min) before the run: $load_before; after: $load_after. \"render\" is rtt_render's"
    echo "share of a frame, \"present\" the streaming texture's update and SDL's present (a frame's mean, ms)."
    echo
    echo "The thesis' Table 6.2 (its garage scene: 89,754 polygons, MFT 16x16 primary rays, mono"
    echo "reflections, packet glass, edge-width shadows, 512x512): Pentium D 2.7 fps on 1 core and"
    echo "5.0 on 2; Core 2 Quad 4.5, 9.0 and 17.4 fps on 1, 2 and 4 cores."
    echo
    for scene in $scenes; do
        echo "## $scene"
        echo
        echo "| kernel | shadows | $(for t in $threads; do printf 'fps, %s thread(s) | Mrays/s | render, present (ms) | ' "$t"; done)"
        echo "|---|---|$(for t in $threads; do printf -- '---:|---:|---:|'; done)"
        for k in $kernels; do
            for s in $(shadows_of "$k"); do
                printf '| %s | %s |' "$k" "$s"
                for t in $threads; do
                    awk -F'\t' -v sc="$scene" -v t="$t" -v k="$k" -v s="$s" \
                        '$1==sc && $2==t && $3==k && $4==s {printf " %s | %s | %s, %s |", $5, $6, $7, $8; found=1} END {if (!found) printf " - | - | - |"}' "$tsv"
                done
                echo
            done
        done
        echo
    done
} >"$md"
echo "viewer-fps: wrote $md"
