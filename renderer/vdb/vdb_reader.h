#pragma once
// What the OpenVDB reader module (vplab_vdb, renderer/vdb/vdb_reader.cpp) hands back: a float grid's active bounding
// box stored densely, without the majorant grid, which renderer/scene/vdb_grid.cpp builds on the renderer's side.

#include <cstdint>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "renderer/scene/vdb_grid.h"

namespace vplab {

struct VdbDense {
  glm::ivec3 first{0};        ///< index of the box's first voxel
  glm::ivec3 size{0};         ///< voxels per axis
  std::vector<float> values;  ///< x fastest, then y, then z; inactive voxels 0
  uint64_t activeVoxels = 0;  ///< voxels OpenVDB marks active
  float minValue = 0.0f;      ///< smallest and largest active value
  float maxValue = 0.0f;
  glm::dmat4 localFromIndex{1.0};  ///< the grid's index-to-world map
};

/// The module's one entry point, found by name with dlsym. Throws VdbError as readVdbDensity documents.
using ReadVdbDenseFunction = void (*)(const std::string& path, const std::string& gridName, VdbDense& out);
inline constexpr const char* kReadVdbDenseSymbol = "vplabReadVdbDense";

}  // namespace vplab
