#include "renderer/gl/density_grid_storage.h"

#include <nanovdb/util/GridBuilder.h>

#include <algorithm>
#include <cstring>

namespace vplab {

const char* toString(DensityGridStorage storage) {
  return storage == DensityGridStorage::Texture ? "3D texture" : "NanoVDB storage buffer";
}

DensityGridStorage densityGridStorage(const DensityGrid& grid, int max3dTextureSize, bool forceBuffer) {
  const glm::ivec3 size = grid.size;
  const bool sidesFit = max3dTextureSize <= 0 || std::max({size.x, size.y, size.z}) <= max3dTextureSize;
  const bool bytesFit = 4.0 * size.x * size.y * static_cast<double>(size.z) <= kMaxDensityTextureBytes;
  return !forceBuffer && sidesFit && bytesFit ? DensityGridStorage::Texture : DensityGridStorage::Buffer;
}

std::vector<uint32_t> nanoVdbFloatGrid(const DensityGrid& grid) {
  nanovdb::GridBuilder<float> builder(0.0f, nanovdb::GridClass::FogVolume);
  const glm::ivec3 last = grid.origin + grid.size - 1;
  const std::size_t sy = static_cast<std::size_t>(grid.size.x), sz = sy * static_cast<std::size_t>(grid.size.y);
  // The builder leaves out the voxels that return the background (0), so only leaves with smoke are stored.
  builder(
      [&](const nanovdb::Coord& ijk) {
        const glm::ivec3 p = glm::ivec3(ijk[0], ijk[1], ijk[2]) - grid.origin;
        return grid.values[static_cast<std::size_t>(p.z) * sz + static_cast<std::size_t>(p.y) * sy +
                           static_cast<std::size_t>(p.x)];
      },
      nanovdb::CoordBBox(nanovdb::Coord(grid.origin.x, grid.origin.y, grid.origin.z),
                         nanovdb::Coord(last.x, last.y, last.z)));
  const nanovdb::GridHandle<> handle = builder.getHandle<>();
  std::vector<uint32_t> words((handle.size() + 3) / 4, 0u);
  std::memcpy(words.data(), handle.data(), handle.size());
  return words;
}

}  // namespace vplab
