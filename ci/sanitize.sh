#!/usr/bin/env bash
# Sanitizer runs:
#  1. -DRTT_SANITIZE=address,undefined in build-asan, then every ctest test
#     (except the fuzz-smoke and sanitize wrappers, which would recurse);
#  2. -DRTT_SANITIZE=thread in build-tsan, then the tests that start threads
#     (the pool, the tile scheduler, the renderers, the builders), selected
#     by TSAN_TESTS, building only their executables (and rtt for the
#     scripts); both steps run JOBS tests at once.  TSan looks for races:
#     the selected tests' single-threaded oracle sweeps (kernels against the
#     reference and the brute force, TSAN_SKIP_CASES) report Skipped there
#     (RTT_TEST_SKIP, tests/case_skip.c); they run whole in the Release
#     suites and under ASan.
# Any report fails the run (-fno-sanitize-recover=all is set by the top-level
# CMake).  Environment: SANITIZE_BUILD_PREFIX (default <root>/build), JOBS
# (default 2), CC (default: the system compiler), TSAN_TESTS (ctest regex),
# TSAN_SKIP_CASES (comma-separated cmocka case names),
# SANITIZE_STEPS ("asan tsan" by default).  LeakSanitizer reads the
# suppressions of fuzz/lsan.supp (a leak inside libassimp, not ours).
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
prefix=${SANITIZE_BUILD_PREFIX:-$root/build}
jobs=${JOBS:-2}
steps=(${SANITIZE_STEPS:-asan tsan})
# the tests that start threads (the pool, the tile scheduler, the renderers,
# the builders); the single-threaded kernel tests gain nothing from TSan
tsan_tests=${TSAN_TESTS:-'^(test_engine_threads|test_optimized_(antialiasing|build|bvh|bvh_frusta|kdt|pgrid|pgrid_shadows|pgrid_soft|render|shadows|transparent_shadows)|test_reference_(render|edge_width)|test_render_cache|mpi_render)$'}
# their cases that start no thread: the kernels and grids against the
# reference and the brute force, one thread each
tsan_skip_cases=${TSAN_SKIP_CASES-test_light_grid_rays_match_reference_and_brute_force,test_soft_grid_rays_match_reference_and_brute_force,test_closest_hits_match_brute_force,test_sah_cost_close_to_reference,test_pgrid_hits_match_reference,test_kernels_on_primary_rays,test_mft_camera_rays,test_kernels_on_random_rays_with_specials,test_kernels_on_shadow_rays,test_mft_camera_drops_back_faces_only_where_no_eye_ray_meets_them_first}
# Leaks inside libassimp on its STL parse-error path are not ours: fuzz/lsan.supp.
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$root/fuzz/lsan.supp}

configure() {   # build-dir sanitizers
  local build=$1 sanitizers=$2
  echo "sanitize: building $build with -fsanitize=$sanitizers"
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRTT_SANITIZE="$sanitizers" \
    > "$build.configure.log" 2>&1 || { cat "$build.configure.log"; exit 1; }
}
configure_and_build() {   # build-dir sanitizers: every target
  configure "$1" "$2"
  cmake --build "$1" -j "$jobs"
}

for step in "${steps[@]}"; do
  case $step in
    asan)
      configure_and_build "$prefix-asan" address,undefined
      ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1} \
      UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1} \
        ctest --test-dir "$prefix-asan" --output-on-failure -j "$jobs" -E '^(fuzz_smoke|sanitize)$'
      ;;
    tsan)
      # only what the selected tests run: each cmocka test's own executable,
      # and rtt for a script (mpi_render)
      # every listed case must exist: a renamed one would silently run again
      for c in ${tsan_skip_cases//,/ }; do
        grep -q "^static void $c(void \*\*state)" "$root"/tests/test_*.c ||
          { echo "sanitize: TSAN_SKIP_CASES names $c, which no test defines" >&2; exit 2; }
      done
      configure "$prefix-tsan" thread
      targets=()
      for t in $(ctest --test-dir "$prefix-tsan" -N -R "$tsan_tests" | sed -n 's/^ *Test *#[0-9]*: *//p'); do
        case $t in
          test_*) targets+=(--target "$t") ;;
          *) targets+=(--target rtt) ;;
        esac
      done
      [ ${#targets[@]} -gt 0 ] || { echo "sanitize: TSAN_TESTS ($tsan_tests) selects no test" >&2; exit 2; }
      cmake --build "$prefix-tsan" -j "$jobs" "${targets[@]}"
      RTT_TEST_SKIP=$tsan_skip_cases TSAN_OPTIONS=${TSAN_OPTIONS:-halt_on_error=1:second_deadlock_stack=1} \
        ctest --test-dir "$prefix-tsan" --output-on-failure -j "$jobs" -R "$tsan_tests" -E '^(fuzz_smoke|sanitize)$'
      ;;
    *) echo "sanitize: unknown step $step (asan or tsan)" >&2; exit 2 ;;
  esac
done
echo "sanitize: ${steps[*]} clean"
