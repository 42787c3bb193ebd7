#!/usr/bin/env bash
# The full conformance suite on the real benchmark scenes (README: "Full
# conformance"): fetches the Quake III maps and CGAL meshes if needed, runs
# `rtt conform` with every ray set on each (reference against every optimized
# traversal mode and Embree), then `rtt conform --extremes` with the closed
# benchmark meshes for watertightness, and conformance/watertight-runs.sh
# (escapes at 100,000 rays per kind).  Reports go to conformance/results/
# (one table per scene); the exit status is non-zero when any
# run exceeds the suite's thresholds (conformance/README.md).
#
# Usage: conformance/run-full.sh [path/to/rtt] [--max-rays N]
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
src=$(dirname "$here")
rtt=${1:-$src/build/cli/rtt}
shift || true
[ -x "$rtt" ] || { echo "run-full: no rtt binary at $rtt (build first or pass its path)" >&2; exit 2; }
data=$(bash "$src/bench/fetch-scenes.sh") || exit 1
out="$here/results"
mkdir -p "$out"
status=0
for scene in "$data"/maps/{oa_dm4,ctf_inyard,czest3ctf}.bsp "$data"/meshes/{bunny00,armadillo,refined_elephant}.off; do
    name=$(basename "${scene%.*}")
    echo "== $name"
    "$rtt" conform "$scene" --rays all "$@" | tee "$out/$name.txt" || status=1
done
echo "== watertight: 100,000 rays per kind from inside the closed meshes"
bash "$here/watertight-runs.sh" "$rtt" "$data/meshes" 100000 | tee "$out/watertight.txt" || status=1
echo "== extremes"
"$rtt" conform --extremes --meshes "$data/meshes" "$@" | tee "$out/extremes.txt" || status=1
echo "run-full: $( [ $status -eq 0 ] && echo conformant || echo 'FAILED (see above)' ); reports in $out"
exit $status
