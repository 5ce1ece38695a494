#!/usr/bin/env bash
# The main job on a fresh Debian 12 machine: installs packages, builds, renders the default scene.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${VPLAB_BUILD_DIR:-$root/build}"
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"
out="$root/out"
mkdir -p "$out"
"$build/app/vplab" reference "$root/assets/scenes/cornell-box.gltf" --spp 256 --size 512x512 \
  --out "$out/cornell-box.exr" --png "$out/cornell-box.png"
