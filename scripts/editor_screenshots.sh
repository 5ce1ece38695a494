#!/usr/bin/env bash
# Regenerates the editor screenshots that docs/editor.md refers to: one per teaching preset, taken by the editor's
# script mode under Xvfb after the preset's offline render (if it starts one) finished and the preview converged.
#
#   scripts/editor_screenshots.sh [out dir]      (default docs/images/editor; build dir from $VPLAB_BUILD_DIR or build/)
#
# Writes <out>/<preset-slug>.png (the whole 1280x720 window) and prints each path. The preset names come from the
# editor itself: an unknown preset name fails at parse time and lists them, one per line.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${VPLAB_BUILD_DIR:-$root/build}"
vplab="$build/app/vplab"
out="${1:-$root/docs/images/editor}"
[ -x "$vplab" ] || { echo "no $vplab: build first (scripts/build.sh)" >&2; exit 1; }
command -v xvfb-run >/dev/null || { echo "xvfb-run is needed (scripts/install-deps.sh installs it)" >&2; exit 1; }
mkdir -p "$out"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

echo "preset ?" > "$work/list.txt"
mapfile -t presets < <("$vplab" edit --script "$work/list.txt" 2>&1 | sed -n 's/^  //p')
[ "${#presets[@]}" -gt 0 ] || { echo "could not list the presets" >&2; exit 1; }

script="$work/shots.txt"
: > "$script"
for name in "${presets[@]}"; do
  slug="$(printf '%s' "$name" | tr 'A-Z' 'a-z' | sed 's/[^a-z0-9]\{1,\}/-/g; s/^-//; s/-$//')"
  {
    echo "preset $name"
    echo "wait-offline"
    echo "frames 3"
    echo "screenshot $out/$slug.png"
  } >> "$script"
done
xvfb-run -a -s "-screen 0 1280x720x24" "$vplab" edit --script "$script" | sed -n 's/^screenshot \([^ ]*\) .*/\1/p'
