#!/usr/bin/env bash
# Long fuzz session: each harness in turn for FUZZ_SECONDS (default 600),
# one at a time, under nice, in libFuzzer's fork mode so that a finding is
# saved and the run goes on (-ignore_crashes/-ignore_timeouts/-ignore_ooms).
# Expects the clang tree of ci/fuzz-smoke.sh (build-fuzz; FUZZ_BUILD to
# change).  New corpus entries go to $FUZZ_BUILD/long-corpus/<harness>/,
# findings to $FUZZ_BUILD/long-artifacts/<harness>/, logs to
# $FUZZ_BUILD/long-<harness>.log; the summary line per harness gives total
# executions, executions per second and findings.
#
#   FUZZ_SECONDS=600 bash fuzz/long-run.sh [harness ...]
set -uo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${FUZZ_BUILD:-$root/build-fuzz}
seconds=${FUZZ_SECONDS:-600}
harnesses=("$@")
[ ${#harnesses[@]} -gt 0 ] || harnesses=(kd_build pgrid kdt scene_json q3bsp exr assimp mesh_header pk3 q3_shader texture)
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$root/fuzz/lsan.supp}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}

for h in "${harnesses[@]}"; do
  corpus="$build/long-corpus/$h" artifacts="$build/long-artifacts/$h" log="$build/long-$h.log"
  mkdir -p "$corpus" "$artifacts"
  args=(-fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 -max_total_time="$seconds"
        -timeout=20 -rss_limit_mb=2048 -artifact_prefix="$artifacts/")
  [ -f "$root/fuzz/dict/$h.dict" ] && args+=(-dict="$root/fuzz/dict/$h.dict")
  asan=detect_leaks=1
  # Assimp is built without frame pointers: only the slow unwinder reaches
  # the frame that fuzz/lsan.supp names.
  [ "$h" = assimp ] && asan=$asan:fast_unwind_on_malloc=0
  start=$(date +%s)
  ASAN_OPTIONS=${ASAN_OPTIONS:-$asan} nice -n 10 "$build/fuzz/fuzz_$h" "${args[@]}" "$corpus" "$root/fuzz/corpus/$h" \
    > "$log" 2>&1
  elapsed=$(( $(date +%s) - start ))
  last=$(grep -E '^#[0-9]+: cov' "$log" | tail -1)
  execs=$(sed -n 's/^#\([0-9]*\):.*/\1/p' <<< "$last")
  rate=$(( ${execs:-0} / (elapsed > 0 ? elapsed : 1) ))
  findings=$(find "$artifacts" -type f | wc -l)
  printf '%-11s %5ss %12s execs %8s execs/s  %s  findings: %s\n' "$h" "$elapsed" "${execs:-?}" "$rate" \
    "$(grep -o 'cov: [0-9]* ft: [0-9]*' <<< "$last")" "$findings" | tee -a "$build/long-summary.txt"
done
