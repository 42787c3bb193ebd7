#!/usr/bin/env bash
# A failure made on purpose is named and replayable: vertex-aimed rays
# (rtt rays --kind vertex) through the projected test, which is not
# watertight, given to `rtt conform --rays-from` (judged as the random set,
# grazing bounded at 0.05%), fail the row.  The JSON must name the first
# failing rays (origin, direction, tnear, tfar, each engine's and the
# referee's prim and t, the record in the --failing-rays file), the file must
# hold every failing ray once, and `rtt trace --rays` on it must give the
# hits the report printed, for the engine and for the reference.
set -u
rtt="$1"
src="$2"
scene="$src/scenes/mat_diffuse.json"
command -v jq >/dev/null || { echo "FAIL: jq not found (ci/install-deps.sh installs it)"; exit 1; }
failures=0
fail() {
    echo "FAIL: $*"
    failures=$((failures + 1))
}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$rtt" rays "$scene" --kind vertex -n 2000 -o "$work/rays.bin" >/dev/null || { echo "FAIL: rtt rays"; exit 1; }
"$rtt" conform "$scene" --rays-from "$work/rays.bin" --engines optimized/mono --isect projected \
    --failing-rays "$work/failing.bin" --json >"$work/out.json" 2>"$work/err.txt"
rc=$?
jq -e . "$work/out.json" >/dev/null 2>&1 || { echo "FAIL: no JSON (exit $rc)"; cat "$work/err.txt"; exit 1; }
[ "$rc" -eq 1 ] || fail "a failing row must exit 1, got $rc"
check() { jq -e "$2" "$work/out.json" >/dev/null || fail "$1 ($2)"; }
check "the row fails on its own errors" '.pass == false and (.rows | length) == 1 and .rows[0].pass == false
    and .rows[0].rays == "file" and .rows[0].count == 2000 and .rows[0].errors.hitmiss_grazing > 1'
check "the first failing rays are named, at most 8" '(.rows[0].failing_rays | length) >= 2
    and (.rows[0].failing_rays | length) <= 8'
check "each names origin, direction, bounds, every hit and its record" 'all(.rows[0].failing_rays[];
    (.org | length) == 3 and (.dir | length) == 3 and .tnear != null and .tfar != null
    and (.engine | has("prim") and has("t")) and (.oracle | has("prim") and has("t"))
    and (.referee | has("prim") and has("t")) and (.file_index | type == "number")
    and .verdict == "engine wrong" and .against_referee == "hit/miss grazing")'
check "every error of the row is in the file" '.failing_ray_count ==
    (.rows[0].errors | .t_mismatch + .hitmiss_grazing + .hitmiss_other + .occluded)'
check "the rays round-trip exactly" '.failing_rays_inexact == 0'
size=$(stat -c %s "$work/failing.bin")
count=$(jq .failing_ray_count "$work/out.json")
[ "$size" -eq $((32 * count)) ] || fail "failing-rays file holds $size bytes for $count rays"
"$rtt" trace "$scene" --rays "$work/failing.bin" --engine optimized --traversal mono --isect projected \
    -o "$work/engine.bin" || fail "rtt trace of the failing rays (engine)"
"$rtt" trace "$scene" --rays "$work/failing.bin" --engine reference -o "$work/reference.bin" ||
    fail "rtt trace of the failing rays (reference)"
python3 - "$work/out.json" "$work/failing.bin" "$work/engine.bin" "$work/reference.bin" <<'PY' || fail "replay"
import json, struct, sys
report = json.load(open(sys.argv[1]))
rays = open(sys.argv[2], "rb").read()
hits = {"engine": open(sys.argv[3], "rb").read(), "oracle": open(sys.argv[4], "rb").read()}
f32 = lambda x: struct.unpack("<f", struct.pack("<f", x))[0]
bad = 0
for note in report["rows"][0]["failing_rays"]:
    k = note["file_index"]
    rec = struct.unpack_from("<8f", rays, 32 * k)
    named = [f32(v) for v in note["org"] + note["dir"]]
    if list(rec[:6]) != named:
        print("record %d is not the ray the report names: %s vs %s" % (k, rec[:6], named)); bad += 1
    for who, data in hits.items():
        t, u, v, prim = struct.unpack_from("<3fI", data, 16 * k)
        want = note[who]
        got = (None, None) if prim == 0xFFFFFFFF else (prim, t)
        if got != (want["prim"], None if want["t"] is None else f32(want["t"])):
            print("record %d, %s: replay gives %s, the report %s" % (k, who, got, want)); bad += 1
sys.exit(1 if bad else 0)
PY
echo "conform_replay: $count failing rays named and replayed, $failures failed"
[ "$failures" -eq 0 ]
