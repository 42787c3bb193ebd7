#!/usr/bin/env bash
# Benchmark smoke (a regression guard): `rtt bench --quick` runs every
# method on a small scene from scenes/, and every full render it makes is the
# image the reference renderer makes (rtt compare, within the tolerances
# below).  No timing is asserted: the machine running the tests may be busy.
#
#   hard, none, multi:N   against `rtt render --engine reference` with the same shadows
#   cone:N, pyramid:N     against the reference's multi:N (the same N samples per pixel)
#   edgewidth             against the reference when it renders edge width, else
#                         against `rtt render` (the bench must not change the image)
# Rows the renderer refuses are listed by the bench as skipped; the test
# reports them and accepts them.
#
# Usage: bench_smoke.sh RTT SOURCE_DIR
set -u
rtt="${1:?usage: bench_smoke.sh RTT SOURCE_DIR}"
src="${2:?usage: bench_smoke.sh RTT SOURCE_DIR}"
scene="$src/scenes/light_sphere.json"
size=96
# An optimized image may differ from the reference's only where the engines
# pick a different triangle on a shared edge: a few pixels.
limits=(--max-share 0.01 --max-rmse 0.02)

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

"$rtt" bench --help >"$work/help" || fail "rtt bench --help exited $?"
grep -q "usage: rtt bench" "$work/help" || fail "rtt bench --help prints no usage"

mkdir -p "$work/images"
if ! "$rtt" bench "$scene" --quick --size "$size" --images "$work/images" --json >"$work/bench.json" \
    2>"$work/bench.err"; then
    fail "rtt bench --quick exited non-zero: $(cat "$work/bench.err")"
    exit 1
fi

# Every kind of row is present and every primary/shadow kernel ran.
for kind in primary shadow render build; do
    grep -q "\"kind\":[[:space:]]*\"$kind\"" "$work/bench.json" || fail "no $kind rows in the report"
done
for method in mono "packet 2x2" "omni 2x2" "frustum 8x8" "mft 8x8" "cone 8x8" "mft-cone 8x8"; do
    grep -q "\"method\":[[:space:]]*\"$method\"" "$work/bench.json" || fail "no row for $method"
done
if grep -q '"error":' "$work/bench.json"; then
    echo "rows the bench skipped (accepted):"
    grep '"error":' "$work/bench.json" | sort -u | sed 's/^[[:space:]]*/    /'
fi

reference() { # shadows -> path of the reference image (rendered once)
    local shadows=$1 out="$work/reference_${1//[:]/_}.exr"
    if [ ! -e "$out" ]; then
        "$rtt" render "$scene" --engine reference --shadows "$shadows" --width "$size" --height "$size" \
            --threads 2 -o "$out" >/dev/null 2>"$work/ref.err" || return 1
    fi
    echo "$out"
}

checked=0
for image in "$work"/images/*.exr; do
    [ -e "$image" ] || break
    name=$(basename "$image" .exr)            # <method>_<shadows>_t<threads>
    shadows=$(echo "$name" | sed -E 's/^(mono|packet_2x2|omni_2x2|[a-z-]+_[0-9]+x[0-9]+)_//; s/_t[0-9]+$//')
    case "$shadows" in
        hard | none) want="$shadows" ;;
        multi_*) want="multi:${shadows#multi_}" ;;
        cone_* | pyramid_*) want="multi:${shadows#*_}" ;;
        edgewidth) want=edgewidth ;;
        *) fail "$name: cannot tell the shadow method from the image name"; continue ;;
    esac
    if ! ref=$(reference "$want"); then
        if [ "$want" != edgewidth ]; then
            fail "$name: the reference cannot render --shadows $want: $(cat "$work/ref.err")"
            continue
        fi
        ref="$work/optimized_edgewidth.exr"
        "$rtt" render "$scene" --shadows edgewidth --traversal mft --tile 8 --width "$size" --height "$size" \
            -o "$ref" >/dev/null 2>&1 || { fail "$name: rtt render --shadows edgewidth failed"; continue; }
    fi
    if ! "$rtt" compare "$image" "$ref" "${limits[@]}" >"$work/compare.out" 2>&1; then
        fail "$name differs from $(basename "$ref"): $(tr '\n' ' ' <"$work/compare.out")"
    fi
    checked=$((checked + 1))
done
[ "$checked" -ge 10 ] || fail "only $checked render images were checked (expected every traversal and shadow method)"

echo "bench_smoke: $checked images checked, $failures failures"
[ "$failures" -eq 0 ]
