#!/usr/bin/env bash
# The whole test suite on a fresh Debian 12 machine: installs packages, builds, runs every test with CTest; then the
# same tests once more in a Debug build under AddressSanitizer and UndefinedBehaviorSanitizer
# (scripts/test-sanitized.sh). VPLAB_SKIP_SANITIZED=1 skips that second run.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${VPLAB_BUILD_DIR:-$root/build}"
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"
# The CPU images the GL tests compare with, rendered once for the whole run: the OSMesa twins and the sanitized run
# read what the first test to ask rendered (tests/cpu_image_cache.h).
VPLAB_TEST_IMAGE_CACHE="$(mktemp -d)"
export VPLAB_TEST_IMAGE_CACHE
trap 'rm -rf "$VPLAB_TEST_IMAGE_CACHE"' EXIT
(cd "$build" && ctest --output-on-failure -j "$(nproc)")
if [ "${VPLAB_SKIP_SANITIZED:-0}" != 1 ]; then
  "$root/scripts/test-sanitized.sh"
fi
