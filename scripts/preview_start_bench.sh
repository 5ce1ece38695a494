#!/usr/bin/env bash
# The headless preview's whole process against a 16-spp 256^2 reference of the same scene, each started after an idle
# pause as a user's would be (docs/benchmarks.md, "The cold headless preview": on a VM whose freed memory goes back to
# the hypervisor, a process started right after another one runs faster than one started after a pause). Per scene and
# round: pause, reference, pause, preview with Mesa's shader cache as it is (warm after the first run), and with
# --cold also pause, preview with an empty shader cache. Prints a table and writes preview_start.csv (or $CSV).
#
# usage: scripts/preview_start_bench.sh [--rounds N] [--pause S] [--cold] [scene.gltf ...]
#        (default: 3 rounds, 6 s pauses, the Cornell box, the fog box and the smoke box)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
vplab="${VPLAB:-$root/build/app/vplab}"
csv="${CSV:-preview_start.csv}"
rounds=3 pause=6 cold=0 scenes=()
while [ $# -gt 0 ]; do
  case "$1" in
    --rounds) rounds="$2"; shift 2 ;;
    --pause) pause="$2"; shift 2 ;;
    --cold) cold=1; shift ;;
    -h|--help) sed -n '2,9p' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) scenes+=("$1"); shift ;;
  esac
done
[ ${#scenes[@]} -gt 0 ] || scenes=("$root/assets/scenes/cornell-box.gltf" "$root/assets/scenes/cornell-fog.gltf" \
                                   "$root/assets/scenes/cornell-smoke.gltf")
[ -x "$vplab" ] || { echo "preview_start_bench: no $vplab (run scripts/build.sh first)" >&2; exit 2; }
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT

# Wall seconds of one run, after the pause; a failed run stops the bench.
timed() {
  sleep "$pause"
  local TIMEFORMAT=%R
  { time "$@" >"$out/log" 2>&1; } 2>"$out/time" || { cat "$out/log" >&2; exit 1; }
  cat "$out/time"
}

echo "scene,round,reference_s,preview_s,ratio,preview_cold_s,ratio_cold" >"$csv"
printf '%-16s %5s %11s %9s %6s %10s %6s\n' scene round reference preview ratio cold ratio
for scene in "${scenes[@]}"; do
  name="$(basename "$scene" .gltf)"
  for ((r = 1; r <= rounds; ++r)); do
    ref=$(timed "$vplab" reference "$scene" --size 256x256 --samples-per-pixel 16 -o "$out/r.png")
    pre=$(timed "$vplab" preview "$scene" --size 640x480 -o "$out/p.png")
    ratio=$(awk -v a="$pre" -v b="$ref" 'BEGIN { printf "%.2f", a / b }')
    coldS="" coldRatio=""
    if [ "$cold" = 1 ]; then
      rm -rf "$out/cache" && mkdir "$out/cache"
      coldS=$(MESA_SHADER_CACHE_DIR="$out/cache" timed "$vplab" preview "$scene" --size 640x480 -o "$out/p.png")
      coldRatio=$(awk -v a="$coldS" -v b="$ref" 'BEGIN { printf "%.2f", a / b }')
    fi
    printf '%-16s %5d %11s %9s %6s %10s %6s\n' "$name" "$r" "$ref" "$pre" "$ratio" "${coldS:--}" "${coldRatio:--}"
    echo "$name,$r,$ref,$pre,$ratio,$coldS,$coldRatio" >>"$csv"
  done
done
echo "wrote $csv"
