#include "renderer/scene/density_grid.h"

#include <cassert>
#include <cmath>

namespace vplab {

DensityGrid DensityGrid::fromDense(glm::ivec3 first, glm::ivec3 size, const std::vector<float>& values,
                                   int majorantCell) {
  assert(values.size() == static_cast<std::size_t>(size.x) * size.y * size.z);
  DensityGrid g;
  g.origin = first - 1;
  g.size = size + 2;
  g.values.assign(static_cast<std::size_t>(g.size.x) * g.size.y * g.size.z, 0.0f);
  g.minValue = std::numeric_limits<float>::infinity();
  g.maxValue = 0.0f;
  for (int z = 0; z < size.z; ++z)
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x) {
        const float v = values[(static_cast<std::size_t>(z) * size.y + y) * size.x + x];
        g.values[(static_cast<std::size_t>(z + 1) * g.size.y + (y + 1)) * g.size.x + (x + 1)] = v;
        g.minValue = std::min(g.minValue, v);
        g.maxValue = std::max(g.maxValue, v);
      }
  g.activeVoxels = values.size();
  if (values.empty()) g.minValue = 0.0f;
  g.buildMajorants(majorantCell);
  return g;
}

float DensityGrid::lookup(const glm::vec3& index) const {
  const glm::vec3 p = index - glm::vec3(origin);
  const glm::vec3 f0 = glm::floor(p);
  const glm::ivec3 i(f0);
  // Outside the stored box (margin included) the density is 0; the margin's zeros make the fall-off inside exact.
  if (i.x < 0 || i.y < 0 || i.z < 0 || i.x + 1 >= size.x || i.y + 1 >= size.y || i.z + 1 >= size.z) return 0.0f;
  const glm::vec3 f = p - f0;
  const std::size_t sx = 1, sy = static_cast<std::size_t>(size.x), sz = sy * static_cast<std::size_t>(size.y);
  const std::size_t base = static_cast<std::size_t>(i.z) * sz + static_cast<std::size_t>(i.y) * sy + i.x;
  const float c00 = values[base] * (1.0f - f.x) + values[base + sx] * f.x;
  const float c10 = values[base + sy] * (1.0f - f.x) + values[base + sy + sx] * f.x;
  const float c01 = values[base + sz] * (1.0f - f.x) + values[base + sz + sx] * f.x;
  const float c11 = values[base + sz + sy] * (1.0f - f.x) + values[base + sz + sy + sx] * f.x;
  const float c0 = c00 * (1.0f - f.y) + c10 * f.y;
  const float c1 = c01 * (1.0f - f.y) + c11 * f.y;
  return c0 * (1.0f - f.z) + c1 * f.z;
}

void DensityGrid::buildMajorants(int cellVoxels) {
  majorantCell = std::max(1, cellVoxels);
  // Cells tile [0, size - 1] in stored coordinates; the last one may reach past it (nothing is there but zeros).
  for (int a = 0; a < 3; ++a) cells[a] = std::max(1, (size[a] - 1 + majorantCell - 1) / majorantCell);
  const std::size_t n = static_cast<std::size_t>(cells.x) * cells.y * cells.z;
  cellMin.assign(n, std::numeric_limits<float>::infinity());
  cellMax.assign(n, 0.0f);
  // A cell spans stored voxels [c S, (c + 1) S] on each axis (both ends: the trilinear interpolation inside reads the
  // voxels on its faces); a voxel on a face bounds the two cells it touches.
  for (int z = 0; z < size.z; ++z)
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x) {
        const float v = values[(static_cast<std::size_t>(z) * size.y + y) * size.x + x];
        const glm::ivec3 p(x, y, z);
        glm::ivec3 lo, hi;
        for (int a = 0; a < 3; ++a) {
          hi[a] = std::min(cells[a] - 1, p[a] / majorantCell);
          lo[a] = std::max(0, p[a] % majorantCell == 0 ? p[a] / majorantCell - 1 : hi[a]);
          lo[a] = std::min(lo[a], hi[a]);
        }
        for (int cz = lo.z; cz <= hi.z; ++cz)
          for (int cy = lo.y; cy <= hi.y; ++cy)
            for (int cx = lo.x; cx <= hi.x; ++cx) {
              const std::size_t k = cellIndex({cx, cy, cz});
              cellMin[k] = std::min(cellMin[k], v);
              cellMax[k] = std::max(cellMax[k], v);
            }
      }
  for (float& m : cellMin)
    if (!std::isfinite(m)) m = 0.0f;
}

std::atomic<uint64_t>& majorantViolations() {
  static std::atomic<uint64_t> count{0};
  return count;
}

}  // namespace vplab
