#!/usr/bin/env bash
# Fuzz smoke run: builds the libFuzzer harnesses with clang
# (-DRTT_FUZZ=ON -DRTT_EMBREE=ON, ASan + UBSan, in build-fuzz) and runs each
# for FUZZ_SECONDS (default 60; JOBS of them at once, so the eleven take about
# six minutes on two cores) over its
# committed seed corpus.  New inputs go to a scratch directory, never into the
# committed corpus.  A crash fails the run and leaves its input in
# build-fuzz/fuzz-artifacts/<harness>/: minimise it (-minimize_crash=1), fix
# the bug, and commit the input under fuzz/regressions/<harness>/ (see
# fuzz/README.md).
#
# Two things that are not ours are tolerated, and only those:
#  - LeakSanitizer reads fuzz/lsan.supp (a leak inside libassimp's STL
#    importer); for the assimp harness the slow unwinder is on, since
#    libassimp has no frame pointers and the fast one stops before the
#    suppressed frame;
#  - Assimp's own parsers hang on some inputs (PLY, see fuzz/README.md): the
#    assimp harness runs in fork mode with -ignore_timeouts=1, and its
#    timeouts are counted and kept in the artifacts, not failed.  Any crash,
#    sanitizer report or broken invariant still fails.
#
# The mutation sequence is seeded (FUZZ_SEED, default 1), so a smoke run is
# a fixed regression guard: the same inputs in the same order on every
# machine, further on a faster one.  A red smoke run is reproducible with the
# same seed; exploring is the long run's job (fuzz/long-run.sh, random seeds).
# FUZZ_SEED=0 asks libFuzzer for a random seed.
#
# Environment: FUZZ_SECONDS, FUZZ_SEED, FUZZ_BUILD (build directory), JOBS
# (default 2: the build's jobs and the harnesses run at once),
# FUZZ_HARNESSES (default: all eleven).
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${FUZZ_BUILD:-$root/build-fuzz}
seconds=${FUZZ_SECONDS:-60}
seed=${FUZZ_SEED:-1}
jobs=${JOBS:-2}
harnesses=(${FUZZ_HARNESSES:-scene_json q3bsp assimp mesh_header kdt kd_build pgrid exr pk3 q3_shader texture})

if ! command -v clang >/dev/null; then
  echo "fuzz-smoke: clang is not installed (ci/install-deps.sh installs it)" >&2
  exit 1
fi

echo "fuzz-smoke: configuring $build"
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DRTT_FUZZ=ON -DRTT_EMBREE=ON > "$build.configure.log" 2>&1 ||
  { cat "$build.configure.log"; exit 1; }
targets=()
for h in "${harnesses[@]}"; do targets+=(--target "fuzz_$h"); done
cmake --build "$build" -j "$jobs" "${targets[@]}"

# Stop at the first UBSan report instead of printing and going on; leaks count.
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$root/fuzz/lsan.supp}
asan_options=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}

# One harness: its run, its verdict and its summary line in $build/fuzz-<h>.result
# (first word ok or CRASH).
run_harness() {
  local h=$1
  local scratch artifacts log timeout args asan start code result elapsed units execs cov hangs note
  scratch=$(mktemp -d)
  artifacts="$build/fuzz-artifacts/$h"
  rm -rf "$artifacts"
  mkdir -p "$artifacts"
  log="$build/fuzz-$h.log"
  timeout=20
  # Assimp's PLY hangs would each eat 20 s of the assimp minute
  [ "$h" = assimp ] && timeout=5
  args=(-seed="$seed" -max_total_time="$seconds" -timeout="$timeout" -rss_limit_mb=2048 -print_final_stats=1
        -artifact_prefix="$artifacts/")
  asan=$asan_options
  if [ "$h" = assimp ]; then
    args+=(-fork=1 -ignore_timeouts=1)
    asan=$asan:fast_unwind_on_malloc=0
  fi
  if [ -f "$root/fuzz/dict/$h.dict" ]; then args+=(-dict="$root/fuzz/dict/$h.dict"); fi
  echo "fuzz-smoke: $h for ${seconds}s"
  start=$(date +%s)
  code=0
  ASAN_OPTIONS=$asan "$build/fuzz/fuzz_$h" "${args[@]}" "$scratch" "$root/fuzz/corpus/$h" > "$log" 2>&1 || code=$?
  # fork mode exits with its last job's code, 70 after a tolerated timeout:
  # for assimp only a crash, leak or oom artifact is a failure
  if [ "$h" = assimp ] && [ "$code" -ne 0 ] && [ -z "$(find "$artifacts" -type f ! -name 'timeout-*')" ] &&
     ! grep -aq "^fuzz:" "$log"; then
    code=0
  fi
  if [ "$code" -eq 0 ]; then
    result=ok
  else
    result=CRASH
    { echo "fuzz-smoke: $h crashed:"
      grep -E "^(fuzz:|==[0-9]+==ERROR|SUMMARY)|runtime error" "$log" | head -5 || true
      ls "$artifacts" || true; } >&2
  fi
  elapsed=$(( $(date +%s) - start ))
  units=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  # fork mode prints no final stats: its last "#<runs>: cov: ..." line counts
  [ -n "$units" ] || units=$(sed -n 's/^#\([0-9]*\): cov.*/\1/p' "$log" | tail -1)
  execs=$(( ${units:-0} / (elapsed > 0 ? elapsed : 1) ))
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 || true)
  hangs=$(find "$artifacts" -name 'timeout-*' | wc -l)
  note=""
  [ "$h" = assimp ] && [ "$hangs" -gt 0 ] && note="  ($hangs Assimp parser hangs tolerated)"
  printf '%-11s %-6s %8s execs/s %10s runs  %s%s\n' "$h" "$result" "$execs" "${units:-?}" "${cov:-}" "$note" \
    > "$build/fuzz-$h.result"
  rm -rf "$scratch"
}

# $jobs harnesses at a time, each a single libFuzzer process on one core:
# the seeded sequence of each is the same as when they ran one by one.
running=0
for h in "${harnesses[@]}"; do
  rm -f "$build/fuzz-$h.result"
  if [ "$running" -ge "$jobs" ]; then wait -n || true; running=$((running - 1)); fi
  run_harness "$h" &
  running=$((running + 1))
done
wait
status=0
summary=()
for h in "${harnesses[@]}"; do
  line=$(cat "$build/fuzz-$h.result" 2>/dev/null || printf '%-11s %-6s (no verdict: the run did not finish)' "$h" CRASH)
  case $line in "$h"*" ok "*) ;; *) status=1 ;; esac
  summary+=("$line")
done

echo "fuzz-smoke: summary (${seconds}s each, seed $seed; logs in $build/fuzz-<harness>.log)"
printf '  %s\n' "${summary[@]}"
exit $status
