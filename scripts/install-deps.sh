#!/usr/bin/env bash
# Installs the Debian 12 packages vplab builds and tests with. Idempotent: it only calls apt-get
# when a package is missing, so it is fast on a machine that already has them.
set -euo pipefail

packages=(
  build-essential cmake pkg-config git
  libglfw3-dev libosmesa6-dev libegl-dev libegl1-mesa-dev libgl-dev libopengl-dev libgl1-mesa-dri
  libimgui-dev libtinygltf-dev libglm-dev libembree-dev libtbb-dev libstb-dev nlohmann-json3-dev
  libtinyexr-dev zlib1g-dev libgtest-dev libgmock-dev libbenchmark-dev xvfb xauth python3-glad
  libopenvdb-dev libboost-iostreams-dev  # density grids (smoke); OpenVDB's CMake module needs Boost iostreams
  libnanovdb-dev                         # the preview's grids too big for a 3D texture (PNanoVDB.h in GLSL)
  python3-openvdb python3-numpy          # scripts/make_smoke.py writes the bundled smoke's grid
  assimp-testmodels  # third-party glTF 2.0 files the tests load (tests/third_party_scenes_test.cpp)
  parallel           # GNU parallel: bench shards in the tests and the documented multi-machine recipe
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
if [ "$(id -u)" -ne 0 ]; then
  echo "install-deps: run as root (apt-get needs it)" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
apt-get update -q
apt-get install -y -q --no-install-recommends "${missing[@]}"
