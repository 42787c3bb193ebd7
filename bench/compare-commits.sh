#!/usr/bin/env bash
# Frame times of two commits on the same machine, in the same run: builds
# BASE and HEAD (default: the working tree's HEAD) in temporary worktrees,
# then runs `rtt bench` of each binary in turn, ROUNDS times per scene, on the
# same views (this tree's bench/views.json) and prints a Markdown table of
# the median frames/s of every primary and render row whose method matches
# METHODS (a regex, default ^mft), with after/before.  Alternating the
# binaries spreads the machine's noise over both.
#
# Usage: bench/compare-commits.sh BASE [HEAD] [--scenes "a b"] [--size N]
#                                 [--threads N] [--frames N] [--rounds N] [--methods REGEX]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
base=${1:?usage: compare-commits.sh BASE [HEAD] [options]}; shift
head=HEAD
if [[ $# -gt 0 && $1 != --* ]]; then head=$1; shift; fi
scenes="oa_dm4 ctf_inyard czest3ctf bunny00 armadillo refined_elephant" size=512 threads=1 frames=5 rounds=3
methods='^mft'
while [[ $# -gt 0 ]]; do
    case $1 in
    --scenes) scenes=$2 ;; --size) size=$2 ;; --threads) threads=$2 ;; --frames) frames=$2 ;;
    --rounds) rounds=$2 ;; --methods) methods=$2 ;;
    *) echo "compare-commits: unknown option $1" >&2; exit 2 ;;
    esac
    shift 2
done
data=$(bash "$root/bench/fetch-scenes.sh")
work=$(mktemp -d)
trap 'git -C "$root" worktree remove --force "$work/base" >/dev/null 2>&1 || true;
      git -C "$root" worktree remove --force "$work/head" >/dev/null 2>&1 || true; rm -rf "$work"' EXIT
for side in base head; do
    rev=$base; [[ $side == head ]] && rev=$head
    git -C "$root" worktree add -q --detach "$work/$side" "$rev"
    cmake -S "$work/$side" -B "$work/$side/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
    cmake --build "$work/$side/build" -j "$(nproc)" --target rtt >/dev/null
done
scene_path() {
    for kind in maps/$1.bsp meshes/$1.off; do [[ -e $data/$kind ]] && { echo "$data/$kind"; return; }; done
    echo "compare-commits: no scene $1 in $data" >&2; exit 1
}
for scene in $scenes; do
    path=$(scene_path "$scene")
    for round in $(seq "$rounds"); do
        for side in base head; do
            "$work/$side/build/cli/rtt" bench "$path" --views "$root/bench/views.json" --only primary,render \
                --size "$size" --threads "$threads" --frames "$frames" --no-embree --json \
                >"$work/$scene.$side.$round.json"
        done
    done
done
python3 - "$work" "$methods" "$rounds" "$base" "$head" "$size" "$threads" $scenes <<'PY'
import json, re, statistics, sys
work, methods, rounds, base, head, size, threads, *scenes = sys.argv[1:]
print(f"| scene | kind | method | {base} fps | {head} fps | after / before |")
print("|---|---|---|---:|---:|---:|")
for scene in scenes:
    fps = {}
    for side in ("base", "head"):
        for r in range(1, int(rounds) + 1):
            rows = json.load(open(f"{work}/{scene}.{side}.{r}.json"))["rows"]
            seen = set()
            for row in rows:
                key = (row["kind"], row["method"], row.get("variant", ""))
                if row["engine"] != "rtt" or not re.search(methods, row["method"]) or key in seen:
                    continue
                if row["kind"] == "render" and key[1:] in {k[1:] for k in seen if k[0] == "render"}:
                    continue
                seen.add(key)
                fps.setdefault(key, {}).setdefault(side, []).append(row["fps"])
    for key, sides in fps.items():
        if "base" not in sides or "head" not in sides:
            continue
        b, h = statistics.median(sides["base"]), statistics.median(sides["head"])
        variant = f" ({key[2]})" if key[2] else ""
        print(f"| {scene} | {key[0]} | {key[1]}{variant} | {b:.1f} | {h:.1f} | {h / b:.3f} |")
PY
