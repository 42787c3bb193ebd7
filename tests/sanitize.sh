#!/usr/bin/env bash
# ctest wrapper for ci/sanitize.sh (bash sanitize.sh <rtt> <source-dir>).
# Two extra full builds (ASan+UBSan, TSan) take too long for every developer
# `make test`: they run only in CI (CI=true) or when asked
# (RTT_SANITIZE_SMOKE=1).
set -euo pipefail
source_dir=${2:?usage: sanitize.sh <rtt> <source-dir>}
if [ "${CI:-}" != "true" ] && [ "${RTT_SANITIZE_SMOKE:-}" != "1" ]; then
  echo "sanitize: not run (set RTT_SANITIZE_SMOKE=1 or CI=true to build and test under ASan/UBSan and TSan)"
  exit 77 # ctest reports Skipped (SKIP_RETURN_CODE)
fi
exec bash "$source_dir/ci/sanitize.sh"
