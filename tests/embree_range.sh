#!/usr/bin/env bash
# The Embree adapter never hands Embree a ray it cannot take: a component of
# 2e18 (Embree asserts, aborting the process, at 1.844e18 and beyond) is
# answered as a miss, exit 0, and the ray next to it is still traced.
set -u
rtt="$1"
src="$2"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$rtt" --help 2>/dev/null | grep -q embree || "$rtt" render --help | grep -q embree || exit 77
python3 - "$work/rays.bin" <<'PY'
import struct, sys
with open(sys.argv[1], "wb") as f:
    f.write(struct.pack("<8f", 2e18, 0, 0, -1, 0, 0, 0, float("inf")))     # origin beyond Embree's range
    f.write(struct.pack("<8f", 0, 0, 5, 2e18, 0, -1e18, 0, float("inf")))  # direction beyond it
    f.write(struct.pack("<8f", 0, 0, 5, 0, 0, -1, 0, float("inf")))        # an ordinary ray
PY
"$rtt" trace "$src/scenes/mat_diffuse.json" --engine embree --rays "$work/rays.bin" -o "$work/hits.bin" ||
    { echo "FAIL: rtt trace --engine embree exited $? on rays beyond Embree's range"; exit 1; }
python3 - "$work/hits.bin" <<'PY'
import struct, sys
d = open(sys.argv[1], "rb").read()
hits = [struct.unpack_from("<3fI", d, 16 * i) for i in range(3)]
assert hits[0][3] == 0xFFFFFFFF and hits[1][3] == 0xFFFFFFFF, hits
assert hits[2][3] != 0xFFFFFFFF, hits
print("embree range: out-of-range rays answered as misses, the ordinary one traced")
PY
