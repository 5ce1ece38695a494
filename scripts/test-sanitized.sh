#!/usr/bin/env bash
# The test suite under AddressSanitizer and UndefinedBehaviorSanitizer, in a Debug build (assertions on; -O1 so the
# path-traced tests stay within minutes; -g1, line tables only, gives the sanitizers' reports the same file:line stack
# frames as -g at about 60 % of the compile time), into build-sanitized/ (or $VPLAB_SANITIZE_BUILD_DIR). Any ASan or
# UBSan finding, and any leak outside Mesa's own libraries (tests/lsan-mesa.supp), fails the test it occurs in.
# $VPLAB_SANITIZE_LABELS picks the CTest labels (a regex for `ctest -L`; default: every test). The statistical tests
# (labels cpu-statistical and gl-statistical, listed in tests/statistical-tests.txt) are left out: their cost is many
# seeds, VPL sets or samples on code paths that quicker tests run under the sanitizers too (checked line by line with
# gcov), and the Release run checks their bounds (docs/benchmarks.md, "The test suite in CI").
# VPLAB_SANITIZE_STATISTICAL=1 runs them as well.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${VPLAB_SANITIZE_BUILD_DIR:-$root/build-sanitized}"
labels="${VPLAB_SANITIZE_LABELS:-.}"
exclude=(-LE statistical)
if [ "${VPLAB_SANITIZE_STATISTICAL:-0}" = 1 ]; then exclude=(); fi
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-g1 -O1" -DVPLAB_SANITIZE=ON \
  -DVPLAB_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" -j "$(nproc)"
export ASAN_OPTIONS="detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1"
export LSAN_OPTIONS="suppressions=$root/tests/lsan-mesa.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
cd "$build"
ctest --output-on-failure -j "$(nproc)" -L "$labels" "${exclude[@]}"
