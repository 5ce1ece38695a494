#pragma once
// What the passes that read the media table (shaders/common/medium.glsl) are compiled for: the number of media, and
// which of them, if any, carries a density grid. Both are shader defines, so that the loops over the media unroll and
// a scene without a grid compiles exactly the homogeneous code it always had (renderer/gl/media_pass.h uploads the
// table and the grid, as a 3D texture or a NanoVDB buffer).

#include <string>
#include <vector>

namespace vplab {

struct MediaShaderLayout {
  int count = 0;        ///< PREVIEW_MEDIA: media in the table (0: none, the transmittance is 1)
  int gridMedium = -1;  ///< PREVIEW_MEDIA_GRID: the table index of the medium with a density grid; -1: none
  /// PREVIEW_MEDIA_GRID_NANOVDB: the grid is read from a NanoVDB storage buffer, not a 3D texture
  /// (renderer/gl/density_grid_storage.h).
  bool gridInBuffer = false;

  std::vector<std::string> defines() const {
    std::vector<std::string> out = {"PREVIEW_MEDIA " + std::to_string(count)};
    if (gridMedium >= 0) out.push_back("PREVIEW_MEDIA_GRID " + std::to_string(gridMedium));
    if (gridMedium >= 0 && gridInBuffer) out.push_back("PREVIEW_MEDIA_GRID_NANOVDB");
    return out;
  }
  bool operator==(const MediaShaderLayout&) const = default;
};

}  // namespace vplab
