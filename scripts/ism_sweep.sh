#!/usr/bin/env bash
# Imperfect shadow maps, speed against accuracy (docs/benchmarks.md "Imperfect shadow maps"): for each tile size and
# point budget, the preview's indirect light with ISM against the exact CPU VPL render of the same VPLs (relMSE and
# energy ratio; the cube-map row gives the floor that the rasterised gather itself leaves), and what a VPL change costs
# on a dense scene (vplab_bench_scale_bench: its VPL maps part and the whole change).
#   scripts/ism_sweep.sh [out-dir]      (after scripts/build.sh; the dense scene from scripts/make_dense_scene.py)
# Writes out-dir/ism_sweep.csv and prints a table.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${VPLAB_BUILD_DIR:-$root/build}"
vplab="$build/app/vplab"
out="${1:-$root/out/ism-sweep}"
mkdir -p "$out"
dense="$root/out/scenes/dense-100000-point.gltf"
[ -f "$dense" ] || python3 "$root/scripts/make_dense_scene.py" --triangles 100000 --light point
scenes=("$root/assets/scenes/cornell-box.gltf" "$root/assets/scenes/two-rooms.gltf" "$dense")
tiles=(32 64 128)
budgets=(524288 1048576 2097152 4194304)
# The preview point-samples pixel centres and the exact render averages 4 jittered samples per pixel: both rows see
# the same edge difference, so the cube row is the floor of what any visibility technique can reach here.
common=(--size 320x240 --vpl-count 256 --clamp-bound 20 --seed 3 --components indirect)
preview=(--interleave 1 --ssbc-steps 0 --gl egl)

metric() { awk -v k="$1" '$1 == k { print $2 }'; }

csv="$out/ism_sweep.csv"
echo "scene,visibility,tile,points,relmse,energy_ratio,vpl_change_ms,vpl_maps_ms" >"$csv"
printf '%-24s %-5s %5s %9s %9s %7s %10s %8s\n' scene vis tile points relMSE energy "change ms" "maps ms"
for scene in "${scenes[@]}"; do
  name="$(basename "$scene" .gltf)"
  exact="$out/$name-exact.exr"
  "$vplab" render "$scene" --method vpl "${common[@]}" --out "$exact" >/dev/null 2>&1
  row() {  # visibility tile points
    local image="$out/$name-$1-$2-$3.exr" relmse energy change="" maps=""
    local flags=(--visibility "$1")
    [ "$1" = ism ] && flags+=(--ism-tile-size "$2" --ism-point-budget "$3")
    "$vplab" preview "$scene" "${common[@]}" "${preview[@]}" "${flags[@]}" --out "$image" >/dev/null
    local metrics
    metrics="$("$vplab" compare "$image" "$exact")"
    relmse="$(metric relmse <<<"$metrics")"
    energy="$(metric energy_ratio <<<"$metrics")"
    if [ "$scene" = "$dense" ] && [ "$1" = ism ]; then
      local timing
      timing="$("$build/bench/vplab_bench_scale_bench" --gl egl --repeats 3 --visibility ism --ism-tile-size "$2" \
        --ism-point-budget "$3" --csv "$out/scale-$2-$3.csv" "$scene" >/dev/null && tail -n 1 "$out/scale-$2-$3.csv")"
      change="$(cut -d, -f6 <<<"$timing")"
      maps="$(cut -d, -f9 <<<"$timing")"
    fi
    echo "$name,$1,$2,$3,$relmse,$energy,$change,$maps" >>"$csv"
    printf '%-24s %-5s %5s %9s %9.5f %7.4f %10s %8s\n' "$name" "$1" "$2" "$3" "$relmse" "$energy" "${change%.*}" "${maps%.*}"
  }
  row cube - -
  for tile in "${tiles[@]}"; do
    for points in "${budgets[@]}"; do row ism "$tile" "$points"; done
  done
done
echo "wrote $csv"
