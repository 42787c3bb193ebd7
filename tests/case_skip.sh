#!/usr/bin/env bash
# RTT_TEST_SKIP (tests/case_skip.c, linked into every cmocka test): the named
# cases report Skipped, each with one note, the others still run, and the
# executable exits 0; unset, every case runs.  ci/sanitize.sh relies on it.
set -u
src=$(realpath "$2")
exe=./test_engine_options # run from the tests' build directory (ctest's working directory)
[ -x "$exe" ] || { echo "case_skip: $exe is not built"; exit 1; }
mapfile -t cases < <(sed -n 's/^ *cmocka_unit_test(\(test_[a-z0-9_]*\)),$/\1/p' "$src/tests/test_engine_options.c")
[ "${#cases[@]}" -ge 3 ] || { echo "case_skip: fewer than 3 cases found in test_engine_options.c"; exit 1; }
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

out=$(RTT_TEST_SKIP="${cases[0]},no_such_case,${cases[2]}" "$exe" 2>&1) || fail "exit $? with two cases skipped"
for c in "${cases[0]}" "${cases[2]}"; do
    grep -qx "\[  SKIPPED \] $c" <<<"$out" || fail "$c was not reported Skipped"
    [ "$(grep -c "^note: $c skipped: it is in RTT_TEST_SKIP$" <<<"$out")" = 1 ] || fail "$c: not one note"
done
grep -qx "\[       OK \] ${cases[1]}" <<<"$out" || fail "${cases[1]} did not run"
[ "$(grep -c '^\[  SKIPPED \]' <<<"$out")" -ge 2 ] || fail "fewer than two Skipped lines"

out=$(env -u RTT_TEST_SKIP "$exe" 2>&1) || fail "exit $? with nothing skipped"
grep -q 'SKIPPED' <<<"$out" && fail "a case was skipped with RTT_TEST_SKIP unset"
[ "$(grep -c '^\[       OK \]' <<<"$out")" = "${#cases[@]}" ] || fail "not every case ran with RTT_TEST_SKIP unset"
out=$(RTT_TEST_SKIP= "$exe" 2>&1) || fail "exit $? with RTT_TEST_SKIP empty"
grep -q 'SKIPPED' <<<"$out" && fail "a case was skipped with RTT_TEST_SKIP empty"

[ "$failures" = 0 ] && echo "case_skip: ok (${#cases[@]} cases)"
[ "$failures" = 0 ]
