#!/usr/bin/env bash
# The main job on a fresh Debian 12 machine: installs packages, builds, then opens the editor on the default scene
# when a display is available ($DISPLAY set), else renders the default scene headless.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${VPLAB_BUILD_DIR:-$root/build}"
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"
scene="$root/assets/scenes/cornell-box.gltf"
if [[ -n "${DISPLAY:-}" && -x "$build/app/vplab" ]] && "$build/app/vplab" --help | grep '^  edit ' >/dev/null; then
  echo "DISPLAY is set: opening the editor on $scene (close the window to finish)"
  exec "$build/app/vplab" edit "$scene"
fi
out="$root/out"
mkdir -p "$out"
echo "no DISPLAY: rendering $scene headless into $out (run 'vplab edit' with a display for the editor)"
vplab="$build/app/vplab"
# The path-traced reference (Embree), then the GL preview of the same scene and settings (EGL or OSMesa), then the
# error of the preview against the reference.
"$vplab" reference "$scene" --samples-per-pixel 256 --size 512x512 --out "$out/reference.exr" --png "$out/reference.png"
"$vplab" preview "$scene" --size 512x512 --clamp-bound 20 --ssbc-steps 2 --interleave 2 \
  --out "$out/preview.exr" --png "$out/preview.png"
"$vplab" compare "$out/preview.exr" "$out/reference.exr" --heatmap "$out/preview-error.png"
echo "images: $out/reference.png $out/preview.png $out/preview-error.png"
