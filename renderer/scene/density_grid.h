#pragma once
// A density grid: the heterogeneous part of a medium read from an OpenVDB float grid (docs/theory.md §22). Voxel
// values sit at integer index coordinates (the OpenVDB convention); between them the density is their trilinear
// interpolation, and it is 0 outside the active voxels. The values are stored densely over the active voxels'
// bounding box widened by one voxel of zeros on every side, so that a lookup never leaves the array and the density
// falls to 0 exactly where OpenVDB's trilinear sampler says it does.
//
// Beside the values a coarse majorant grid keeps, for each block of kMajorantCell^3 voxels, the smallest and largest
// value that the trilinear interpolation can take inside it (those of the voxels at its corners and inside): delta
// tracking samples tentative collisions from the largest, residual ratio tracking takes the smallest as its control.

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <glm/glm.hpp>
#include <limits>
#include <string>
#include <vector>

namespace vplab {

/// Largest dense grid accepted, in voxels (4 bytes each: 1 GiB). A grid needs its bounding box dense on the CPU and
/// as a 3D texture in GL; a bigger one is refused with its size instead of exhausting memory.
inline constexpr uint64_t kMaxDensityGridVoxels = uint64_t(1) << 28;
/// Voxels along each edge of a majorant cell by default (the reference walks the ray cell by cell).
inline constexpr int kMajorantCell = 8;

struct DensityGrid {
  std::string source;    ///< the file it was read from (empty for a grid made in code)
  std::string gridName;  ///< the grid's name in that file
  glm::ivec3 origin{0};  ///< index coordinates of values[0] (the first zero voxel of the margin)
  glm::ivec3 size{0};    ///< stored voxels along x, y, z (margin included); x varies fastest
  std::vector<float> values;
  uint64_t activeVoxels = 0;  ///< voxels OpenVDB marks active (all stored ones but the margin, for a made grid)
  float minValue = 0.0f;      ///< smallest and largest active value
  float maxValue = 0.0f;
  /// The grid's own index-to-world map (OpenVDB's linear transform): positions in its medium's node frame.
  glm::dmat4 localFromIndex{1.0};

  /// A grid of size.x * size.y * size.z values (x fastest) whose first value sits at index `first`; adds the zero
  /// margin and builds the majorant grid. Values must be finite and >= 0 (readVdbDensity checks them as it reads).
  static DensityGrid fromDense(glm::ivec3 first, glm::ivec3 size, const std::vector<float>& values,
                               int majorantCell = kMajorantCell);

  /// Trilinear density at a point in index coordinates; 0 outside the stored box.
  float lookup(const glm::vec3& index) const;
  /// Lower and upper corner of the box where the density can be non-zero, in index coordinates.
  glm::vec3 boxLower() const { return glm::vec3(origin); }
  glm::vec3 boxUpper() const { return glm::vec3(origin + size - 1); }

  // The majorant grid.
  int majorantCell = kMajorantCell;  ///< voxels per cell edge
  glm::ivec3 cells{0};               ///< cells along x, y, z
  std::vector<float> cellMin, cellMax;
  /// Rebuilds cellMin / cellMax for cells of `cellVoxels` voxels per edge (>= 1).
  void buildMajorants(int cellVoxels);
  std::size_t cellIndex(glm::ivec3 c) const {
    return (static_cast<std::size_t>(c.z) * cells.y + c.y) * cells.x + c.x;
  }
  std::size_t bytes() const { return (values.size() + cellMin.size() + cellMax.size()) * sizeof(float); }
};

/// Counts tracking steps that found the density above its cell's majorant or below its minorant: both are bugs of the
/// majorant grid (the estimators would be biased), so tests require the count to stay 0.
std::atomic<uint64_t>& majorantViolations();

/// A piece [t0, t1) of a ray inside one majorant cell, with the cell's density bounds.
struct MajorantPiece {
  float t0 = 0.0f, t1 = 0.0f;
  float densityMin = 0.0f, densityMax = 0.0f;
};

/// Walks the majorant cells crossed by the ray index(t) = o + t d for t in [t0, t1) (3D DDA, Amanatides & Woo 1987),
/// calling visit(piece) in order; visit returns false to stop. o and d are in index coordinates.
template <class Visit>
void walkMajorants(const DensityGrid& grid, const glm::vec3& o, const glm::vec3& d, float t0, float t1, Visit&& visit) {
  if (!(t1 > t0)) return;
  // Cell coordinates: (index - origin) / majorantCell, cells cover [0, cells).
  const float inv = 1.0f / static_cast<float>(grid.majorantCell);
  const glm::vec3 co = (o - glm::vec3(grid.origin)) * inv;
  const glm::vec3 cd = d * inv;
  const glm::vec3 start = co + cd * t0;
  glm::ivec3 cell = glm::clamp(glm::ivec3(glm::floor(start)), glm::ivec3(0), grid.cells - 1);
  glm::ivec3 step(0);
  glm::vec3 tNext(std::numeric_limits<float>::infinity()), tDelta(std::numeric_limits<float>::infinity());
  for (int a = 0; a < 3; ++a) {
    if (cd[a] > 0.0f) {
      step[a] = 1;
      tNext[a] = (static_cast<float>(cell[a] + 1) - co[a]) / cd[a];
      tDelta[a] = 1.0f / cd[a];
    } else if (cd[a] < 0.0f) {
      step[a] = -1;
      tNext[a] = (static_cast<float>(cell[a]) - co[a]) / cd[a];
      tDelta[a] = -1.0f / cd[a];
    }
  }
  float t = t0;
  while (t < t1) {
    const int axis = tNext.x < tNext.y ? (tNext.x < tNext.z ? 0 : 2) : (tNext.y < tNext.z ? 1 : 2);
    const float exit = std::min(t1, std::max(t, tNext[axis]));
    const std::size_t k = grid.cellIndex(cell);
    if (exit > t && !visit(MajorantPiece{t, exit, grid.cellMin[k], grid.cellMax[k]})) return;
    t = exit;
    cell[axis] += step[axis];
    if (cell[axis] < 0 || cell[axis] >= grid.cells[axis]) return;
    tNext[axis] += tDelta[axis];
  }
}

}  // namespace vplab
