#!/usr/bin/env bash
# The triangle tests' trade (watertight against projected): for each triangle test (watertight,
# projected) x kernel (every kd and BVH kernel; Embree as the peer; the
# reference), time per primary frame (one run, both tests for the kd
# kernels, the BVH's default test) and, against a double-precision brute force
# (bench/accuracy/oracle.c), the escape rate from inside closed meshes (random
# and vertex-aimed rays), t error (max and mean relative) and hit/miss at
# shared edges, at scales 1e-20, 1e-10, 1, 1e10, 1e20 and offsets 1, 1e3,
# 1e5, 1e7.  Writes bench/results/accuracy.json (every row), the tables of
# bench/results/accuracy.md between its generated markers, and
# bench/results/accuracy.png (gnuplot).
#
#   bench/accuracy.sh [--rtt build/cli/rtt] [--rays N] [--frames N]
#                     [--timing-only | --accuracy-only]
#
# --timing-only reruns only the timing (for a quiet machine) and keeps the
# accuracy rows of the existing JSON; --accuracy-only the reverse.  Needs the
# bench meshes (bash bench/fetch-scenes.sh): bunny00.off for the timing and
# as the second closed mesh (the first is a UV sphere built here).
set -eu
cd "$(dirname "$0")/.."
rtt=build/cli/rtt
rays=4096
frames=3
timing=1
accuracy=1
while [ $# -gt 0 ]; do
    case "$1" in
    --rtt) rtt="$2"; shift 2 ;;
    --rays) rays="$2"; shift 2 ;;
    --frames) frames="$2"; shift 2 ;;
    --timing-only) accuracy=0; shift ;;
    --accuracy-only) timing=0; shift ;;
    -h | --help) sed -n '2,20p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "accuracy.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
    esac
done
[ -x "$rtt" ] || { echo "accuracy.sh: $rtt is not an executable (build first, or give --rtt)" >&2; exit 1; }
meshes="${RTT_DATA_DIR:-$HOME/.cache/rtt-data}/meshes"
bunny="$meshes/bunny00.off"
out=bench/results
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

if [ "$timing" -eq 1 ]; then
    [ -f "$bunny" ] || { echo "accuracy.sh: $bunny is missing (bash bench/fetch-scenes.sh)" >&2; exit 1; }
    load=$(cut -d' ' -f1-3 /proc/loadavg)
    # one run: the kd kernels with both tests, the BVH kernels (the default test: watertight) and Embree
    "$rtt" bench "$bunny" --views bench/views.json --only primary --threads 1 --frames "$frames" \
        --compare-isects --json >"$work/timing-kd.json"
    python3 - "$work" "$load" "$(cut -d' ' -f1-3 /proc/loadavg)" "$frames" <<'PY'
import json, sys
work, load_before, load_after, frames = sys.argv[1:]
rows = []
d = json.load(open(f"{work}/timing-kd.json"))
for r in d["rows"]:
    if r.get("kind") == "primary":
        rows.append(r)
json.dump({"rows": rows, "load_before": load_before, "load_after": load_after, "frames": int(frames),
           "mesh": "bunny00.off", "view": "bench/views.json:bunny00", "threads": 1}, open(f"{work}/timing.json", "w"))
PY
fi
if [ "$accuracy" -eq 1 ]; then
    cc -O2 -o "$work/oracle" bench/accuracy/oracle.c -lm
    python3 bench/accuracy/sweep.py --rtt "$rtt" --oracle "$work/oracle" --work "$work" --rays "$rays" \
        --meshes "$meshes" --out "$work/sweep.json"
fi
args=(--json "$out/accuracy.json" --md "$out/accuracy.md" --dat "$work/accuracy.dat")
[ "$timing" -eq 1 ] && args+=(--timing "$work/timing.json")
[ "$accuracy" -eq 1 ] && args+=(--sweep "$work/sweep.json" --rays "$rays")
python3 bench/accuracy/report.py "${args[@]}"
gnuplot -e "dat='$work/accuracy.dat'; out='$out/accuracy.png'" bench/accuracy/accuracy.gp
echo "accuracy.sh: wrote $out/accuracy.json, $out/accuracy.md and $out/accuracy.png"
