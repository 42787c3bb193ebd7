#!/usr/bin/env bash
# Scenes keep their precision wherever they are: a small mesh far from the
# origin is stored relative to its centre (no triangle lost, `rtt info`
# reports the bounds, camera and light in the scene's own coordinates, read
# in double), rays.bin given to
# `rtt trace` in the scene's own coordinates hit what they aim at, and a
# scene whose tiny triangles still collapse says so in one warning line.
set -u
rtt="$1"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# a 1e-3 square 1e5 from the origin: in absolute float its spacing is 8e-3
cat >"$work/far.json" <<'JSON'
{"meshes": [{"vertices": [[0,0,0],[0.001,0,0],[0.001,0.001,0],[0,0.001,0]], "triangles": [[0,1,2],[0,2,3]],
  "transform": {"translate": [100000, 100000, 100000]}}]}
JSON
"$rtt" info "$work/far.json" >"$work/info" 2>"$work/err" || fail "rtt info far.json exited $?"
grep -q "triangles   2 (0 degenerate)" "$work/info" || fail "far square lost triangles: $(grep triangles "$work/info")"
grep -q "bounds      (100000, 100000, 100000) .. (100000.001, 100000.001, 100000)" "$work/info" ||
    fail "bounds not in the scene's coordinates: $(grep bounds "$work/info")"
[ -s "$work/err" ] && fail "unexpected warning: $(cat "$work/err")"

# its camera and light far out too, read in double and reported in the
# scene's own coordinates (float's spacing at 1e5 is 0.008)
cat >"$work/far_camera.json" <<'JSON'
{"camera": {"eye": [100000.3, 100000.2, 100002], "look_at": [100000.25, 100000.5, 100000]},
 "lights": [{"position": [100000.7, 100001.1, 100001.9]}],
 "meshes": [{"vertices": [[0,0,0],[0.001,0,0],[0.001,0.001,0],[0,0.001,0]], "triangles": [[0,1,2],[0,2,3]],
  "transform": {"translate": [100000, 100000, 100000]}}]}
JSON
"$rtt" info "$work/far_camera.json" >"$work/info" 2>"$work/err" || fail "rtt info far_camera.json exited $?"
grep -q "eye (100000.3, 100000.2, 100002), look-at (100000.25, 100000.5, 100000)" "$work/info" ||
    fail "camera not kept in double: $(grep camera "$work/info")"
grep -q "point  at (100000.7, 100001.1, 100001.9)" "$work/info" || fail "light not kept in double: $(grep ' at ' "$work/info")"

# one ray down -z onto the square's centre, in the scene's own coordinates
python3 - "$work/rays.bin" <<'PY'
import struct, sys
with open(sys.argv[1], "wb") as f:
    f.write(struct.pack("<8f", 100000.0005, 100000.0005, 100001, 0, 0, -1, 0, float("inf")))
PY
for isect in watertight projected; do
    "$rtt" trace "$work/far.json" --rays "$work/rays.bin" -o "$work/hits.bin" --isect "$isect" ||
        fail "rtt trace ($isect) exited $?"
    python3 - "$work/hits.bin" "$isect" <<'PY' || fail "trace ($isect) missed the far square"
import struct, sys
t, u, v, prim = struct.unpack("<3fI", open(sys.argv[1], "rb").read())
ok = prim in (0, 1) and abs(t - 1.0) < 1e-3
print(f"{sys.argv[2]}: prim {prim} t {t}")
sys.exit(0 if ok else 1)
PY
done

# rtt rays writes the scene's own coordinates (rtt trace reads those): the
# primary rays of a unit square 1e5 away (big enough for float rays there:
# rays.bin is float), traced, mostly hit it (shifted twice, all miss)
cat >"$work/far_unit.json" <<'JSON'
{"meshes": [{"vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]], "triangles": [[0,1,2],[0,2,3]],
  "transform": {"translate": [100000, 100000, 100000]}}]}
JSON
"$rtt" rays "$work/far_unit.json" --kind primary -n 1024 --seed 3 -o "$work/primary.bin" >/dev/null ||
    fail "rtt rays far_unit.json exited $?"
"$rtt" trace "$work/far_unit.json" --rays "$work/primary.bin" -o "$work/primary.hits" >/dev/null ||
    fail "rtt trace of rtt rays' primary rays exited $?"
python3 - "$work/primary.hits" <<'PY' || fail "rtt rays' primary rays of the far square miss it"
import struct, sys
data = open(sys.argv[1], "rb").read()
hits = sum(1 for i in range(0, len(data), 16) if struct.unpack_from("<3fI", data, i)[3] != 0xFFFFFFFF)
print(f"primary rays: {hits} of {len(data) // 16} hit")
sys.exit(0 if hits > len(data) // 16 // 10 else 1)
PY

# large and far: not centred, so its 1e-6 triangle collapses: one warning line
cat >"$work/collapse.json" <<'JSON'
{"meshes": [{"vertices": [[-1e5,-1e5,0],[1e5,-1e5,0],[0,1e5,0]], "triangles": [[0,1,2]]},
            {"vertices": [[0,0,0],[1e-6,0,0],[0,1e-6,0]], "triangles": [[0,1,2]],
             "transform": {"translate": [100000, 100000, 0]}}]}
JSON
"$rtt" info "$work/collapse.json" >"$work/info" 2>"$work/err" || fail "rtt info collapse.json exited $?"
[ "$(wc -l <"$work/err")" -eq 1 ] || fail "expected one warning line, got: $(cat "$work/err")"
grep -q "warning: .*collapse.json: 1 of 2 triangles collapse" "$work/err" || fail "warning text: $(cat "$work/err")"

[ "$failures" -eq 0 ] && echo "scene precision: all checks passed"
exit $((failures > 0))
