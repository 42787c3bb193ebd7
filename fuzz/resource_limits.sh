#!/usr/bin/env bash
# Resource limits: a hostile scene must not make either
# kd-tree builder use unbounded memory or time.  Both builders stop splitting
# at a maximum depth (default round(2 + log2 N), at least 8, never above 64) and when
# the triangle references in leaves would pass a cap (default 16 N + 1M), and
# `rtt info` reports both.  This builds both trees of scenes made to defeat
# a kd-tree and checks, from `rtt info`:
#   - depth <= maximum and references <= cap, for both engines;
#   - the build finishes within TIME_LIMIT seconds and MEMORY_LIMIT_MB of
#     resident memory (generous bounds: hostile means quadratic or
#     exponential without the limits, not a slow machine).
# Scenes (inline JSON meshes, generated with a fixed seed):
#   haystack   N long thin triangles through the whole box in random
#              directions: every split cuts nearly every triangle;
#   stack      N copies of one large triangle: no plane separates them;
#   star       N triangles sharing one vertex, fanned around it;
#   grid       N/6 full-size quads per axis, evenly spaced: a kd-tree that
#              kept splitting would hold (N/6)^3 cells of 6 references each;
#   deep       the haystack again with --max-depth 64 (the hard limit).
#
#   bash fuzz/resource_limits.sh <rtt> [N]      (ctest: fuzz_resource_limits)
set -euo pipefail
rtt=${1:?usage: resource_limits.sh <rtt> [triangles]}
n=${2:-20000}
time_limit=${TIME_LIMIT:-120}
memory_limit_mb=${MEMORY_LIMIT_MB:-1500}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

python3 - "$work" "$n" <<'PY'
import json, math, random, sys
out, n = sys.argv[1], int(sys.argv[2])
rng = random.Random(6)
def write(name, vertices, triangles):
    with open(f"{out}/{name}.json", "w") as f:
        json.dump({"meshes": [{"vertices": vertices, "triangles": triangles}]}, f)
def unit():
    z = rng.uniform(-1, 1); a = rng.uniform(0, 2 * math.pi); r = math.sqrt(1 - z * z)
    return (r * math.cos(a), r * math.sin(a), z)
v, t = [], []
for i in range(n):   # a stick through the box: two far ends and a point just off the first
    c = [rng.uniform(-1, 1) for _ in range(3)]; d = unit(); e = unit()
    p = [c[k] - 2 * d[k] for k in range(3)]; q = [c[k] + 2 * d[k] for k in range(3)]
    w = [p[k] + 1e-3 * e[k] for k in range(3)]
    t.append([len(v), len(v) + 1, len(v) + 2]); v += [p, q, w]
write("haystack", v, t)
write("stack", [[0, 0, 0], [1, 0, 0], [0, 1, 0]] * n, [[3 * i, 3 * i + 1, 3 * i + 2] for i in range(n)])
k, v, t = max(1, n // 6), [], []
for axis in range(3):
    for i in range(k):
        x, base = -1 + 2 * (i + 0.5) / k, len(v)
        for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            p = [0, 0, 0]; p[axis] = x; p[(axis + 1) % 3] = a; p[(axis + 2) % 3] = b; v.append(p)
        t += [[base, base + 1, base + 2], [base, base + 2, base + 3]]
write("grid", v, t)
v = [[0, 0, 0]] + [[math.cos(2 * math.pi * i / n), math.sin(2 * math.pi * i / n), (i % 7) / 7.0] for i in range(n)]
write("star", v, [[0, 1 + i, 1 + (i + 1) % n] for i in range(n)])
PY

status=0
for scene in haystack stack star grid deep; do
  info="$work/$scene.info" file=$scene options=()
  [ "$scene" = deep ] && file=haystack options=(--max-depth 64)
  if ! /usr/bin/time -f '%e %M' -o "$work/$scene.time" timeout "$time_limit" "$rtt" info "$work/$file.json" \
       --engine both "${options[@]}" > "$info" 2>&1; then
    echo "resource_limits: $scene: rtt info failed or took over ${time_limit}s"; cat "$info"; status=1; continue
  fi
  read -r seconds rss_kb < "$work/$scene.time"
  # "depth  D (maximum M)" and "references R, duplication X (cap C)", one pair per engine
  depths=$(sed -n 's/^ *depth *\([0-9]*\) (maximum \([0-9]*\)).*/\1 \2/p' "$info")
  refs=$(sed -n 's/^ *references *\([0-9]*\),.*(cap \([0-9]*\)).*/\1 \2/p' "$info")
  engines=$(grep -c 'kd-tree' "$info" || true)
  if [ "$engines" -ne 2 ] || [ "$(wc -l <<< "$depths")" -ne 2 ] || [ "$(wc -l <<< "$refs")" -ne 2 ]; then
    echo "resource_limits: $scene: cannot read depth and references of two trees from rtt info"; cat "$info"; status=1; continue
  fi
  while read -r depth max; do
    [ "$depth" -le "$max" ] && [ "$max" -le 64 ] || { echo "resource_limits: $scene: depth $depth > maximum $max"; status=1; }
  done <<< "$depths"
  while read -r references cap; do
    [ "$references" -le "$cap" ] || { echo "resource_limits: $scene: $references references > cap $cap"; status=1; }
  done <<< "$refs"
  if [ $(( rss_kb / 1024 )) -gt "$memory_limit_mb" ]; then
    echo "resource_limits: $scene: peak memory $(( rss_kb / 1024 )) MiB > ${memory_limit_mb} MiB"; status=1
  fi
  printf 'resource_limits: %-8s %6d triangles  %6.1fs  %5d MiB  depth/max %s  references/cap %s\n' "$scene" "$n" \
    "$seconds" $(( rss_kb / 1024 )) "$(tr '\n' ' ' <<< "$depths" | sed 's/ \([0-9]*\) /\/\1, /; s/ \([0-9]*\) $/\/\1/')" \
    "$(tr '\n' ' ' <<< "$refs" | sed 's/ \([0-9]*\) /\/\1, /; s/ \([0-9]*\) $/\/\1/')"
done
exit $status
