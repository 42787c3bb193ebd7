#!/usr/bin/env bash
# `rtt conform SCENE --json` is JSON a machine can read (jq, installed by
# ci/install-deps.sh), and it holds the counts: every row names its engine,
# oracle and ray set, its categories sum to its rays, "pass" follows the
# thresholds of conformance/README.md, and the exit status follows "pass".
# One small scene, every ray set, 512 rays per set: a few seconds.
set -u
rtt="$1"
src="$2"
scene="$src/scenes/mesh_obj.json"
if ! command -v jq >/dev/null; then
    echo "FAIL: jq not found (ci/install-deps.sh installs it)"
    exit 1
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$rtt" conform "$scene" --rays all --engines optimized,reference --max-rays 512 --json >"$work/out.json" \
    2>"$work/err.txt"
rc=$?
failures=0
fail() {
    echo "FAIL: $*"
    failures=$((failures + 1))
}
if ! jq -e . "$work/out.json" >/dev/null 2>&1; then
    echo "FAIL: rtt conform --json did not print JSON (exit $rc)"
    sed 's/^/    /' "$work/out.json" "$work/err.txt" | head -40
    exit 1
fi
check() { # description, jq filter that must yield true
    jq -e "$2" "$work/out.json" >/dev/null || fail "$1 ($2)"
}
check "top-level fields" '(.scene | type == "string") and (.triangles | type == "number") and .triangles > 0
    and (.magnitude | type == "number") and (.pass | type == "boolean") and (.rows | type == "array")'
check "thresholds" '.thresholds.grazing_share_optimized == 0.0005 and .thresholds.grazing_share_embree == 0.01'
# optimized expands to the seven kd and three BVH traversal modes, plus the reference: 11 engines x 4 sets.
check "one row per engine and set" '(.rows | length) == 48
    and ([.rows[].rays] | unique) == ["extreme", "primary", "random", "shadow"]
    and ([.rows[].engine] | unique | length) == 12 and all(.rows[]; .oracle == "reference")'
check "every count is a non-negative integer" 'all(.rows[]; [.count, .agree, .tie, .boundary, .t_mismatch,
    .hitmiss_grazing, .hitmiss_other, .occluded_mismatch][] | type == "number" and . >= 0 and . == floor)'
check "categories sum to the rays of the row" 'all(.rows[];
    .agree + .tie + .boundary + .t_mismatch + .hitmiss_grazing + .hitmiss_other + .unspecified == .count)'
check "rays per set within --max-rays, and some traced" 'all(.rows[]; .count <= 512) and all(.rows[]; .count > 0)'
check "grazing reported on the extreme set, bounded elsewhere" 'all(.rows[];
    if .rays == "extreme" then .grazing_limit == 1 else .grazing_limit == 0.0005 end)'
check "a row's errors are among its disagreements" 'all(.rows[];
    (.errors | .t_mismatch + .hitmiss_grazing + .hitmiss_other + .occluded)
    <= .t_mismatch + .hitmiss_grazing + .hitmiss_other + .occluded_mismatch
    and .errors.occluded <= .occluded_mismatch and .unspecified == 0)'
check "every disagreement is refereed (the budget holds here)" 'all(.rows[]; .unrefereed == 0
    and .refereed == .t_mismatch + .hitmiss_grazing + .hitmiss_other + .occluded_mismatch
    and .refereed == .errors.t_mismatch + .errors.hitmiss_grazing + .errors.hitmiss_other + .errors.occluded
        + .reference_wrong + .both_right + .embree_wrong and .embree_wrong == 0)'
check "pass follows the thresholds on the row's own errors" 'all(.rows[]; .pass == (.errors.t_mismatch == 0
    and .errors.hitmiss_other == 0 and .errors.occluded == 0 and (.error == null)
    and .errors.hitmiss_grazing <= ([.grazing_limit * .count, 1] | max)))'
check "failing rays named on failing rows only" 'all(.rows[]; if .pass then (.failing_rays | length) == 0
    else (.failing_rays | length) > 0 end)'
check "report pass is every row's" '.pass == all(.rows[]; .pass)'
check "the reference agrees with itself (boundary hits aside)" 'all(.rows[] | select(.engine == "reference");
    .agree + .boundary == .count and .agree > 0 and .occluded_mismatch == 0)'
check "the same rays for every engine" '[.rows[] | select(.rays == "random") | .count] | unique | length == 1'
pass=$(jq -r .pass "$work/out.json")
if [ "$pass" = true ] && [ "$rc" -ne 0 ]; then fail "pass is true but the exit status is $rc"; fi
if [ "$pass" = false ] && [ "$rc" -ne 1 ]; then fail "pass is false but the exit status is $rc (expected 1)"; fi
if [ "$pass" != true ]; then fail "mesh_obj.json does not conform"; fi
echo "conform_json: $(jq '.rows | length' "$work/out.json") rows, exit $rc, $failures failed"
[ "$failures" -eq 0 ]
