#!/usr/bin/env bash
# The test suite under AddressSanitizer and UndefinedBehaviorSanitizer, in a Debug build (assertions on; -O1 so the
# path-traced tests stay within minutes; -g1, line tables only, gives the sanitizers' reports the same file:line stack
# frames as -g at about 60 % of the compile time), into build-sanitized/ (or $VPLAB_SANITIZE_BUILD_DIR). Any ASan or
# UBSan finding, and any leak outside Mesa's own libraries (tests/lsan-mesa.supp), fails the test it occurs in.
# $VPLAB_SANITIZE_LABELS picks the CTest labels (a regex for `ctest -L`; default: every test). Left out, and run by
# the Release suite (docs/benchmarks.md, "The test suite in CI"):
# - the statistical tests (labels cpu-statistical and gl-statistical, listed in tests/statistical-tests.txt): their
#   cost is many seeds, VPL sets or samples on code paths that quicker tests run under the sanitizers too (checked
#   line by line with gcov); VPLAB_SANITIZE_STATISTICAL=1 runs them as well;
# - the OSMesa instances of the suites run on both backends (label gl-osmesa-twin): the same renders and CPU
#   references as their EGL twins through the same code but the context's, which the context tests take on OSMesa;
#   VPLAB_SANITIZE_TWINS=1 runs them as well.
# A CTest test runs a whole gtest suite here (VPLAB_CTEST_PER_SUITE, tests/CMakeLists.txt): a sanitized test process
# takes about half a second to start and exit. `build-sanitized/tests/vplab_tests --gtest_filter=...` runs single tests.
# Run from scripts/test.sh, the GL tests take the CPU images they compare with from the Release run's
# (VPLAB_TEST_IMAGE_CACHE, tests/cpu_image_cache.h): the CPU renderers run under the sanitizers in their own tests.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${VPLAB_SANITIZE_BUILD_DIR:-$root/build-sanitized}"
labels="${VPLAB_SANITIZE_LABELS:-.}"
left_out=()
[ "${VPLAB_SANITIZE_STATISTICAL:-0}" = 1 ] || left_out+=(statistical)
[ "${VPLAB_SANITIZE_TWINS:-0}" = 1 ] || left_out+=(osmesa-twin)
exclude=()
if [ "${#left_out[@]}" -gt 0 ]; then exclude=(-LE "$(IFS='|'; echo "${left_out[*]}")"); fi
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-g1 -O1" -DVPLAB_SANITIZE=ON \
  -DVPLAB_BUILD_BENCH=OFF -DVPLAB_CTEST_PER_SUITE=ON >/dev/null
cmake --build "$build" -j "$(nproc)"
export ASAN_OPTIONS="detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1"
export LSAN_OPTIONS="suppressions=$root/tests/lsan-mesa.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
cd "$build"
ctest --output-on-failure -j "$(nproc)" -L "$labels" "${exclude[@]}"
