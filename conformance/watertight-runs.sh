#!/usr/bin/env bash
# Escapes from closed meshes, 100,000 rays per kind (the target: none escapes through a watertight path):
# for every closed mesh in DIR (default ${RTT_DATA_DIR:-~/.cache/rtt-data}/meshes,
# bench/fetch-scenes.sh fetches them), rays of two kinds written by
# `rtt rays` (inside: from a point inside, aimed exactly at every vertex and
# edge midpoint, sampled to N; inside-random: from that point in random
# directions) are traced by the reference, every optimized kd and BVH kernel
# with the watertight and the projected test, and Embree.  An escape is a
# miss in intersect() or a "not occluded" in occluded(): every one of these
# rays must hit the mesh.  (Rays aimed at vertices from outside are no such
# measure: one aimed at a silhouette vertex touches the mesh at that point
# only, and its rounded direction may pass it.)
# Usage: conformance/watertight-runs.sh RTT [DIR] [N]   (prints a table; exits 1
# when the reference or a kernel with the watertight test lets a ray escape;
# a kernel that refuses the watertight test is named, not counted)
set -u
rtt="$1"
dir="${2:-${RTT_DATA_DIR:-$HOME/.cache/rtt-data}/meshes}"
n="${3:-100000}"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
kernels="mono packet omni frustum mft cone mft-cone"
bvh_kernels="bvh-mono bvh-packet bvh-mft"
measure() {
    printf '%-22s %-14s %-24s %-10s %8s %7s %10s %8s\n' mesh kind engine isect rays misses unoccluded escapes
    for mesh in "$dir"/*.off "$dir"/*.ply "$dir"/*.obj; do
        [ -f "$mesh" ] || continue
        name=$(basename "$mesh")
        for kind in inside inside-random; do
            "$rtt" rays "$mesh" --kind $kind -n "$n" -o "$work/$kind.bin" --seed 1 >/dev/null 2>"$work/err" ||
                { echo "$name: $(cat "$work/err")"; continue 2; }
        done
        run() { # label isect args...
            local label="$1" isect="$2"
            shift 2
            for kind in inside inside-random; do
                "$rtt" trace "$mesh" --rays "$work/$kind.bin" -o "$work/hits" "$@" 2>"$work/trace-err" &&
                    "$rtt" trace "$mesh" --rays "$work/$kind.bin" -o "$work/occl" --occluded "$@" 2>"$work/trace-err" || {
                    printf '%-22s %-14s %-24s %-10s %s\n' "$name" "$kind" "$label" "$isect" "$(head -c 150 "$work/trace-err")"
                    continue
                }
                python3 - "$work/hits" "$work/occl" "$name" "$kind" "$label" "$isect" <<'PY'
import struct, sys
hits, occl = open(sys.argv[1], "rb").read(), open(sys.argv[2], "rb").read()
n = len(occl)
miss = [struct.unpack_from("<I", hits, 16 * i + 12)[0] == 0xFFFFFFFF for i in range(n)]
unocc = [occl[i] == 0 for i in range(n)]
print("%-22s %-14s %-24s %-10s %8d %7d %10d %8d" % (sys.argv[3], sys.argv[4], sys.argv[5], sys.argv[6], n,
      sum(miss), sum(unocc), sum(1 for i in range(n) if miss[i] or unocc[i])))
PY
            done
        }
        run reference watertight --engine reference
        for isect in watertight projected; do
            for k in $kernels; do run "optimized/$k" $isect --engine optimized --traversal $k --isect $isect; done
            for k in $bvh_kernels; do run "optimized/$k" $isect --engine optimized --accel bvh --traversal $k --isect $isect; done
        done
        if "$rtt" trace --help | grep -q "embree ("; then run embree robust --engine embree; fi
    done
}
measure | tee "$work/table"
awk '$4 == "watertight" && $5 ~ /^[0-9]+$/ && $8 > 0 { bad = 1 } END { exit bad }' "$work/table"
