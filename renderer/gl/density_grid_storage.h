#pragma once
// Where the preview keeps a density grid (docs/methods.md "Smoke in the preview"): as an R32F 3D texture, whose
// linear filtering is the grid's trilinear interpolation (fastest on llvmpipe), or, for a grid no 3D texture of the
// context holds, as a NanoVDB float grid (Museth 2021) in a shader storage buffer that the shaders read through
// NanoVDB's PNanoVDB.h (shaders/common/medium.glsl), eight voxel reads per lookup.

#include <cstdint>
#include <string>
#include <vector>

#include "renderer/scene/density_grid.h"

namespace vplab {

enum class DensityGridStorage { Texture, Buffer };

const char* toString(DensityGridStorage storage);

/// The most bytes of 3D texture one grid may take in the preview (256 MiB, 2^26 voxels): a larger grid goes to the
/// NanoVDB buffer, which holds only the 8^3 leaves with a non-zero voxel; a smoke plume's bounding box is mostly empty.
inline constexpr double kMaxDensityTextureBytes = 256.0 * 1024 * 1024;

/// The storage for `grid`: the texture while each side fits `max3dTextureSize` (0: not known, not checked) and its
/// bytes kMaxDensityTextureBytes, unless `forceBuffer` (Settings::previewGridInBuffer).
DensityGridStorage densityGridStorage(const DensityGrid& grid, int max3dTextureSize, bool forceBuffer);

/// The grid's non-zero values as a NanoVDB float grid with background 0, indexed like the grid (voxel (i, j, k) holds
/// the value at index (i, j, k)), as the 32-bit words a storage buffer holds. Every voxel it leaves out reads 0, as
/// DensityGrid::lookup's do, so that the same trilinear interpolation of it is the same density.
std::vector<uint32_t> nanoVdbFloatGrid(const DensityGrid& grid);

}  // namespace vplab
