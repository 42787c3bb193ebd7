#!/usr/bin/env bash
# Fuzz smoke run: builds the libFuzzer harnesses with clang
# (-DRTT_FUZZ=ON -DRTT_EMBREE=ON, ASan + UBSan, in build-fuzz) and runs each
# for FUZZ_SECONDS (default 60; six harnesses stay under 10 minutes) over its
# committed seed corpus.  New inputs go to a scratch directory, never into the
# committed corpus.  A crash fails the run and leaves its input in
# build-fuzz/fuzz-artifacts/<harness>/: minimise it (-minimize_crash=1), fix
# the bug, and commit the input under fuzz/regressions/<harness>/.
#
# Environment: FUZZ_SECONDS, FUZZ_BUILD (build directory), JOBS (default 2),
# FUZZ_HARNESSES (default: all six).
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${FUZZ_BUILD:-$root/build-fuzz}
seconds=${FUZZ_SECONDS:-60}
jobs=${JOBS:-2}
harnesses=(${FUZZ_HARNESSES:-scene_json q3bsp assimp kdt kd_build exr})

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
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}

status=0
summary=()
for h in "${harnesses[@]}"; do
  scratch=$(mktemp -d)
  artifacts="$build/fuzz-artifacts/$h"
  mkdir -p "$artifacts"
  log="$build/fuzz-$h.log"
  args=(-max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 -print_final_stats=1
        -artifact_prefix="$artifacts/")
  if [ -f "$root/fuzz/dict/$h.dict" ]; then args+=(-dict="$root/fuzz/dict/$h.dict"); fi
  echo "fuzz-smoke: $h for ${seconds}s"
  if "$build/fuzz/fuzz_$h" "${args[@]}" "$scratch" "$root/fuzz/corpus/$h" > "$log" 2>&1; then
    result=ok
  else
    result=CRASH
    status=1
    grep -E "^(fuzz:|==[0-9]+==ERROR|SUMMARY)|runtime error" "$log" | head -5 >&2 || true
    ls "$artifacts" >&2 || true
  fi
  execs=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  units=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 || true)
  summary+=("$(printf '%-11s %-6s %8s execs/s %10s runs  %s' "$h" "$result" "${execs:-?}" "${units:-?}" "${cov:-}")")
  rm -rf "$scratch"
done

echo "fuzz-smoke: summary (${seconds}s each; logs in $build/fuzz-<harness>.log)"
printf '  %s\n' "${summary[@]}"
exit $status
