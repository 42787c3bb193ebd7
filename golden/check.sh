#!/usr/bin/env bash
# One golden comparison (registered by golden/tests.cmake):
#   check.sh RTT SOURCE_DIR NAME SCENE "OPTIONS" TRAVERSAL MAX_RMSE MAX_ERROR MAX_SHARE
# renders SCENE with the optimized engine in TRAVERSAL mode and compares it
# with golden/NAME.exr under the manifest's tolerances (rtt compare --json
# prints the metrics; its thresholds decide the exit status).
set -u
rtt="$1" src="$2" name="$3" scene="$4" options="$5" traversal="$6"
max_rmse="$7" max_error="$8" max_share="$9"
golden="$src/golden/$name.exr"
[ -f "$golden" ] || { echo "no golden image $golden (run golden/regenerate)"; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# each traversal is its accel's: the perspective grid's, the BVH's (bvh-*), else the kd-tree's
case "$traversal" in
    pgrid) accel=pgrid ;;
    bvh-*) accel=bvh ;;
    *) accel=kd ;;
esac
# shellcheck disable=SC2086  # options is a list of words
"$rtt" render "$src/$scene" --engine optimized --accel "$accel" --traversal "$traversal" $options --threads 2 -o "$work/out.exr" ||
    exit 1
"$rtt" compare "$golden" "$work/out.exr" --json \
    --max-rmse "$max_rmse" --max-error "$max_error" --max-share "$max_share"
