// The OpenVDB reader, a module of its own (vplab_vdb) that renderer/scene/vdb_grid.cpp opens on the first .vdb file:
// libopenvdb's 57k symbol bindings cost every process that links it about 20-50 ms at start on two cores, before
// main (docs/benchmarks.md, "The cold headless preview"), and only scenes with smoke read a .vdb.

#include "renderer/vdb/vdb_reader.h"

#include <openvdb/openvdb.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <filesystem>
#include <mutex>

namespace vplab {

namespace {

void initializeOnce() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "none" : out;
}

/// Opens the file, turning OpenVDB's exceptions into one-line VdbErrors.
std::unique_ptr<openvdb::io::File> openFile(const std::string& path) {
  initializeOnce();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw VdbError("'" + path + "': no such file");
  if (!std::filesystem::is_regular_file(path, ec)) throw VdbError("'" + path + "': not a regular file");
  auto file = std::make_unique<openvdb::io::File>(path);
  try {
    file->open(false);  // no delayed loading: the grid is read whole and the file closed
  } catch (const std::exception& e) {
    throw VdbError("'" + path + "': not a readable OpenVDB file (" + e.what() + ")");
  }
  return file;
}

}  // namespace

}  // namespace vplab

extern "C" __attribute__((visibility("default"))) void vplabReadVdbDense(const std::string& path,
                                                                          const std::string& gridName,
                                                                          vplab::VdbDense& out) {
  using namespace vplab;
  std::unique_ptr<openvdb::io::File> file = openFile(path);
  openvdb::GridBase::Ptr base;
  std::vector<std::string> present;
  try {
    for (auto it = file->beginName(); it != file->endName(); ++it) present.push_back(it.gridName());
    if (std::find(present.begin(), present.end(), gridName) == present.end()) {
      file->close();
      throw VdbError("'" + path + "' has no grid named '" + gridName + "' (grids: " + join(present) + ")");
    }
    base = file->readGrid(gridName);
    file->close();
  } catch (const VdbError&) {
    throw;
  } catch (const std::exception& e) {
    throw VdbError("'" + path + "': cannot read grid '" + gridName + "' (" + e.what() + ")");
  }
  const std::string at = "'" + path + "' grid '" + gridName + "': ";
  openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
  if (!grid) throw VdbError(at + "holds " + base->valueType() + " values; a density grid must be float");
  if (grid->getGridClass() == openvdb::GRID_LEVEL_SET)
    throw VdbError(at + "is a level set (signed distances, not densities); convert it to a fog volume first "
                        "(OpenVDB's tools::sdfToFogVolume, or Blender's Mesh to Volume)");
  if (!grid->transform().isLinear())
    throw VdbError(at + "has a non-linear (frustum) transform; only linear index-to-world maps are read");
  const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
  if (box.empty() || grid->activeVoxelCount() == 0) throw VdbError(at + "has no active voxels: the medium is empty");

  // The active bounding box is stored densely: refuse it before allocating when it is too big.
  const openvdb::Coord dim = box.dim();
  const uint64_t voxels = uint64_t(dim.x() + 2) * uint64_t(dim.y() + 2) * uint64_t(dim.z() + 2);
  if (voxels > kMaxDensityGridVoxels) {
    char text[256];
    std::snprintf(text, sizeof text,
                  "active voxels span %d x %d x %d: %.3g voxels, %.0f MiB stored densely, over the bound of %.3g "
                  "voxels (%.0f MiB)",
                  dim.x(), dim.y(), dim.z(), static_cast<double>(voxels), static_cast<double>(voxels) * 4.0 / 1048576.0,
                  static_cast<double>(kMaxDensityGridVoxels), static_cast<double>(kMaxDensityGridVoxels) * 4.0 / 1048576.0);
    throw VdbError(at + text);
  }

  // Active values (voxels and tiles) into the dense box; inactive voxels stay 0.
  const glm::ivec3 first(box.min().x(), box.min().y(), box.min().z());
  const glm::ivec3 size(dim.x(), dim.y(), dim.z());
  std::vector<float> values(static_cast<std::size_t>(size.x) * size.y * size.z, 0.0f);
  float lowest = std::numeric_limits<float>::infinity(), highest = 0.0f;
  for (auto it = grid->cbeginValueOn(); it; ++it) {
    const float v = *it;
    lowest = std::min(lowest, v);
    highest = std::max(highest, v);
    if (!(v >= 0.0f && std::isfinite(v))) {
      const openvdb::Coord c = it.getCoord();
      char text[160];
      std::snprintf(text, sizeof text, "active voxel (%d, %d, %d) holds %g: densities must be finite and >= 0",
                    c.x(), c.y(), c.z(), static_cast<double>(v));
      throw VdbError(at + text);
    }
    const openvdb::CoordBBox cells = it.getBoundingBox();
    for (int z = cells.min().z(); z <= cells.max().z(); ++z)
      for (int y = cells.min().y(); y <= cells.max().y(); ++y)
        for (int x = cells.min().x(); x <= cells.max().x(); ++x)
          values[(static_cast<std::size_t>(z - first.z) * size.y + (y - first.y)) * size.x + (x - first.x)] = v;
  }
  out.first = first;
  out.size = size;
  out.values = std::move(values);
  out.activeVoxels = grid->activeVoxelCount();
  out.minValue = lowest;
  out.maxValue = highest;
  // The grid's own index-to-world map, read by mapping the index origin and unit axes (OpenVDB's matrices use the
  // row-vector convention; mapping points needs no convention).
  const openvdb::math::Transform& xf = grid->transform();
  const openvdb::Vec3d o = xf.indexToWorld(openvdb::Vec3d(0.0, 0.0, 0.0));
  glm::dmat4 m(1.0);
  for (int a = 0; a < 3; ++a) {
    openvdb::Vec3d e(0.0, 0.0, 0.0);
    e[a] = 1.0;
    const openvdb::Vec3d p = xf.indexToWorld(e) - o;
    m[a] = glm::dvec4(p.x(), p.y(), p.z(), 0.0);
  }
  m[3] = glm::dvec4(o.x(), o.y(), o.z(), 1.0);
  out.localFromIndex = m;
}
