#!/usr/bin/env bash
# The whole test suite on a fresh Debian 12 machine: installs packages, builds, runs every test with CTest; then the
# same tests once more in a Debug build under AddressSanitizer and UndefinedBehaviorSanitizer
# (scripts/test-sanitized.sh). VPLAB_SKIP_SANITIZED=1 skips that second run.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${VPLAB_BUILD_DIR:-$root/build}"
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"
(cd "$build" && ctest --output-on-failure -j "$(nproc)")
if [ "${VPLAB_SKIP_SANITIZED:-0}" != 1 ]; then
  "$root/scripts/test-sanitized.sh"
fi
