#!/usr/bin/env bash
# Interleaved sampling and the discontinuity filter, measured: the error of
# --shadows interleaved:N (N = 4, 8, 16, 32, with and without the filter, and
# with the refining pass :refine) against multi:256, beside multi:16 and
# multi:64, per scene and image size.
# Every image is the reference renderer's (the image the optimized
# interleaved:N and a frusta kernel reproduce); no timing.
#
#   bench/interleaved.sh [RTT]      RTT: the rtt binary (default build/cli/rtt)
#
# Scenes: RTT_INTERLEAVED_SCENES (default: light_sphere light_quad
# shadow_occluder_sizes shadow_on_shadow, from scenes/); sizes:
# RTT_INTERLEAVED_SIZES (default 128 256 512), square.  Output:
# bench/results/interleaved.json (one row per image: scene, size, method,
# and `rtt compare --json`'s fields) and the tables of
# bench/results/interleaved-tables.md; the figures are discussed in
# bench/results/interleaved.md.  Threads: RTT_INTERLEAVED_THREADS (default 2;
# the renders are deterministic, the count changes nothing but the time).
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
rtt=${1:-${RTT:-$root/build/cli/rtt}}
results=${RTT_INTERLEAVED_RESULTS:-$here/results}
scenes=${RTT_INTERLEAVED_SCENES:-light_sphere light_quad shadow_occluder_sizes shadow_on_shadow}
sizes=${RTT_INTERLEAVED_SIZES:-128 256 512}
threads=${RTT_INTERLEAVED_THREADS:-2}

[ -x "$rtt" ] || { echo "interleaved.sh: no rtt binary at $rtt (build it, or pass its path)" >&2; exit 2; }
for tool in jq python3; do
    command -v "$tool" >/dev/null || { echo "interleaved.sh: needs $tool" >&2; exit 2; }
done
mkdir -p "$results"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
rows=$work/rows.jsonl
: >"$rows"

methods="multi:16 multi:64"
for n in 4 8 16 32; do methods="$methods interleaved:$n interleaved:$n:nofilter interleaved:$n:refine"; done

for scene in $scenes; do
    file=$root/scenes/$scene.json
    [ -f "$file" ] || { echo "interleaved.sh: no scene $file" >&2; exit 2; }
    for size in $sizes; do
        opts=(--engine reference --width "$size" --height "$size" --threads "$threads")
        echo "$scene ${size}x$size: truth (multi:256)" >&2
        "$rtt" render "$file" "${opts[@]}" --shadows multi:256 -o "$work/truth.exr" >/dev/null
        for method in $methods; do
            "$rtt" render "$file" "${opts[@]}" --shadows "$method" -o "$work/image.exr" >/dev/null
            "$rtt" compare "$work/image.exr" "$work/truth.exr" --json |
                jq -c --arg scene "$scene" --argjson size "$size" --arg method "$method" \
                    '{scene: $scene, size: $size, method: $method} + .' | tee -a "$rows" >&2
        done
    done
done

python3 - "$rows" "$results" <<'EOF'
import json, sys
rows = [json.loads(line) for line in open(sys.argv[1]) if line.strip()]
out = sys.argv[2]
with open(f"{out}/interleaved.json", "w") as f:
    json.dump({"truth": "reference multi:256", "rows": rows}, f, indent=1)
methods = list(dict.fromkeys(r["method"] for r in rows))
keys = list(dict.fromkeys((r["scene"], r["size"]) for r in rows))
rmse = {(r["scene"], r["size"], r["method"]): r["rmse"] for r in rows}
md = ["# interleaved:N against multi:256 (bench/interleaved.sh)", "",
      "RMSE against the reference renderer's multi:256, every image the reference's.  "
      "`within multi:64`: the filtered interleaved:16 image's RMSE is no higher than multi:64's; "
      "`refined within`: the same for interleaved:16:refine (the second pass).", "",
      "| scene | size | " + " | ".join(methods) + " | within multi:64 | refined within |",
      "|---|---:|" + "---:|" * len(methods) + "---|---|"]
for scene, size in keys:
    cells = [f"{rmse.get((scene, size, m), float('nan')):.5f}" for m in methods]
    bound = rmse.get((scene, size, "multi:64"), 0)
    ok = rmse.get((scene, size, "interleaved:16"), 1) <= bound
    refined = rmse.get((scene, size, "interleaved:16:refine"), 1) <= bound
    md.append(f"| {scene} | {size} | " + " | ".join(cells) + f" | {'yes' if ok else 'no'} | {'yes' if refined else 'no'} |")
with open(f"{out}/interleaved-tables.md", "w") as f:
    f.write("\n".join(md) + "\n")
EOF
echo "interleaved.sh: wrote $results/interleaved.json and interleaved-tables.md" >&2
