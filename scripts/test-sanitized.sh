#!/usr/bin/env bash
# The test suite under AddressSanitizer and UndefinedBehaviorSanitizer, in a Debug build (assertions on, -O1 so the
# path-traced tests stay within minutes), into build-sanitized/ (or $VPLAB_SANITIZE_BUILD_DIR). Any ASan or UBSan
# finding, and any leak outside Mesa's own libraries (tests/lsan-mesa.supp), fails the test it occurs in.
# $VPLAB_SANITIZE_LABELS picks the CTest labels (a regex for `ctest -L`; default: every test). The statistical tests
# (labels cpu-statistical and gl-statistical, listed in tests/CMakeLists.txt) are left out: their cost is many seeds,
# VPL sets or samples of code paths that quicker tests run under the sanitizers too, and their bounds are checked in
# the Release run (docs/guide.md, "Testing"). VPLAB_SANITIZE_STATISTICAL=1 runs them as well.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${VPLAB_SANITIZE_BUILD_DIR:-$root/build-sanitized}"
labels="${VPLAB_SANITIZE_LABELS:-.}"
exclude=(-LE statistical)
if [ "${VPLAB_SANITIZE_STATISTICAL:-0}" = 1 ]; then exclude=(); fi
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-g -O1" -DVPLAB_SANITIZE=ON \
  -DVPLAB_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" -j "$(nproc)"
export ASAN_OPTIONS="detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1"
export LSAN_OPTIONS="suppressions=$root/tests/lsan-mesa.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
cd "$build"
ctest --output-on-failure -j "$(nproc)" -L "$labels" "${exclude[@]}"
