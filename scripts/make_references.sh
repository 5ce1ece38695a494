#!/usr/bin/env bash
# Regenerates the stored reference images in assets/references/ that the regression tests compare against.
# Run only on purpose (the tests never call it): a new reference changes what "correct" means.
#   scripts/make_references.sh [path/to/vplab]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
vplab="${1:-${VPLAB_BUILD_DIR:-$root/build}/app/vplab}"
out="$root/assets/references"
mkdir -p "$out"

# 64x64 at 16384 spp: its own relMSE (~c/16384) is far below what the 16-spp test render shows (~c/16), so the
# test's tolerance is set by the test render's noise alone. Seed 1000 keeps it independent of the tests' seeds.
"$vplab" reference "$root/assets/scenes/cornell-box.gltf" --size 64x64 --samples-per-pixel 16384 --seed 1000 --max-depth 64 \
  --out "$out/cornell-box-64.exr" --png "$out/cornell-box-64.png"
