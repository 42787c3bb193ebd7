#!/usr/bin/env bash
# The Embree adapter never hands Embree a ray it cannot take, for every input
# class: components at or beyond 1.844e18 (Embree asserts there, aborting the
# process), NaN and infinite origins, directions and bounds, empty intervals,
# a zero direction.  Those are answered as misses (intersect and occluded),
# exit 0; rays it can take (tnear = -inf, subnormal components, -0.0, a
# component just below the limit) are traced, and the ordinary ones hit what
# the reference hits.  `rtt conform --rays-from` counts the rays rtt takes but
# Embree cannot as "unspecified" for Embree, apart, and passes.
set -u
rtt="$1"
src="$2"
scene="$src/scenes/mat_diffuse.json"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$rtt" trace --help | grep -q "embree (" || exit 77
command -v jq >/dev/null || { echo "FAIL: jq not found (ci/install-deps.sh installs it)"; exit 1; }
# expect: miss (refused, a miss), hit (must hit what the reference hits), any (traced, no abort)
python3 - "$work/rays.bin" "$work/expect.txt" <<'PY'
import struct, sys
inf, nan = float("inf"), float("nan")
rays = [
    ("miss", "origin beyond Embree's range", (2e18, 0, 0), (-1, 0, 0), 0, inf),
    ("miss", "direction beyond it", (0, 0, 5), (2e18, 0, -1e18), 0, inf),
    ("miss", "negative origin beyond it", (0, -3e19, 0.1), (0, 1, 0), 0, inf),
    ("any", "origin just below the limit", (1.8e18, 0, 0), (-1, 0, 0), 0, inf),
    ("miss", "NaN origin", (nan, 0, 5), (0, 0, -1), 0, inf),
    ("miss", "NaN direction", (0, 0, 5), (0, nan, -1), 0, inf),
    ("miss", "NaN tnear", (0, 0, 5), (0, 0, -1), nan, inf),
    ("miss", "NaN tfar", (0, 0, 5), (0, 0, -1), 0, nan),
    ("miss", "infinite origin", (inf, 0, 5), (0, 0, -1), 0, inf),
    ("miss", "infinite direction", (0, 0, 5), (0, 0, -inf), 0, inf),
    ("miss", "tnear = +inf", (0, 0, 5), (0, 0, -1), inf, inf),
    ("miss", "tfar = -inf", (0, 0, 5), (0, 0, -1), -inf, -inf),
    ("miss", "tnear = tfar", (0, 0, 5), (0, 0, -1), 2, 2),
    ("miss", "zero direction", (0, 0, 5), (0, -0.0, 0), 0, inf),
    ("hit", "tnear = -inf", (0.1, 1.1, 5), (0, 0, -1), -inf, inf),
    ("hit", "subnormal direction components", (0.1, 1.1, 5), (1e-40, -1e-42, -1), 0, inf),
    ("hit", "a subnormal origin component", (1e-42, 1.1, 5), (0, 0, -1), 0, inf),
    ("any", "all-subnormal direction", (0, 0, 5), (1e-40, 1e-41, -1e-40), 0, inf),
    ("hit", "-0.0 components", (0.1, 1.1, 5), (-0.0, 0.0, -1), 0, inf),
    ("hit", "an ordinary ray", (0.1, 1.1, 5), (0, 0, -1), 0, inf),
]
with open(sys.argv[1], "wb") as f, open(sys.argv[2], "w") as e:
    for expect, what, o, d, tn, tf in rays:
        f.write(struct.pack("<8f", *o, *d, tn, tf))
        e.write("%s\t%s\n" % (expect, what))
PY
failures=0
fail() {
    echo "FAIL: $*"
    failures=$((failures + 1))
}
for engine in embree reference; do
    "$rtt" trace "$scene" --engine $engine --rays "$work/rays.bin" -o "$work/$engine.hits" ||
        fail "rtt trace --engine $engine exited $? on the range classes"
    "$rtt" trace "$scene" --engine $engine --rays "$work/rays.bin" --occluded -o "$work/$engine.occl" ||
        fail "rtt trace --engine $engine --occluded exited $? on the range classes"
done
python3 - "$work/expect.txt" "$work/embree.hits" "$work/embree.occl" "$work/reference.hits" <<'PY' || fail "answers"
import struct, sys
expect = [l.rstrip("\n").split("\t") for l in open(sys.argv[1])]
hits = open(sys.argv[2], "rb").read()
occl = open(sys.argv[3], "rb").read()
ref = open(sys.argv[4], "rb").read()
bad = 0
for i, (kind, what) in enumerate(expect):
    prim = struct.unpack_from("<3fI", hits, 16 * i)[3]
    ref_prim = struct.unpack_from("<3fI", ref, 16 * i)[3]
    if kind == "miss" and (prim != 0xFFFFFFFF or occl[i] != 0):
        print("%s: answered prim %d occluded %d, expected a miss" % (what, prim, occl[i])); bad += 1
    if kind == "hit" and (prim == 0xFFFFFFFF or prim != ref_prim or occl[i] != 1):
        print("%s: prim %d occluded %d, the reference prim %d" % (what, prim, occl[i], ref_prim)); bad += 1
sys.exit(1 if bad else 0)
PY
"$rtt" conform "$scene" --engines embree --rays-from "$work/rays.bin" --json >"$work/conform.json" 2>"$work/err.txt"
rc=$?
[ "$rc" -eq 0 ] || { fail "rtt conform --rays-from exited $rc"; sed 's/^/    /' "$work/err.txt" | head; }
jq -e '.rows[0].unspecified == 3 and .rows[0].count == 20 and .rows[0].pass' "$work/conform.json" >/dev/null ||
    fail "conform: expected the 3 rays beyond Embree's range unspecified, the row passing: $(jq -c '.rows[0] |
        {count, agree, unspecified, t_mismatch, hitmiss_grazing, hitmiss_other, embree_wrong, pass}' "$work/conform.json")"
echo "embree_range: 20 input classes, $failures failed"
[ "$failures" -eq 0 ]
