#pragma once
// Density grids from OpenVDB files (docs/scenes.md, "Smoke"), read with OpenVDB itself.

#include <memory>
#include <stdexcept>
#include <string>

#include "renderer/scene/density_grid.h"

namespace vplab {

/// A .vdb file that cannot give a density grid; the message is one line (the loader puts the file and the glTF path
/// in front of it).
struct VdbError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Reads the float grid `gridName` of the OpenVDB file at `path` into a dense DensityGrid with its majorant grid.
/// Refuses, with what it found: an unreadable file, no grid of that name (the names present are listed), a grid that is
/// not float, a level set (signed distances are not densities), a non-linear (frustum) transform, no active voxel,
/// a negative or non-finite active value, and a bounding box over kMaxDensityGridVoxels.
std::shared_ptr<const DensityGrid> readVdbDensity(const std::string& path, const std::string& gridName);

}  // namespace vplab
