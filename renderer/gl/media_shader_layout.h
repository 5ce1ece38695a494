#pragma once
// What the passes that read the media table (shaders/common/medium.glsl) are compiled for: the number of media, which
// of them carry a density grid, and which of those grids are read from the NanoVDB buffer. All are shader defines, so
// that the loops over the media and over the grids unroll and a scene without a grid compiles exactly the homogeneous
// code it always had (renderer/gl/media_pass.h uploads the table, renderer/gl/density_grids_gpu.h the grids).

#include <string>
#include <vector>

namespace vplab {

struct MediaShaderLayout {
  int count = 0;  ///< PREVIEW_MEDIA: media in the table (0: none, the transmittance is 1)
  /// PREVIEW_MEDIA_GRIDS and PREVIEW_MEDIA_GRID_MEDIA: the table indices of the media with a density grid, in table
  /// order; grid g of the shaders is medium gridMedia[g]. Empty: none.
  std::vector<int> gridMedia;
  /// PREVIEW_MEDIA_GRID_NANOVDB: bit g set where grid g is read from the NanoVDB storage buffer, not a 3D texture
  /// (renderer/gl/density_grid_storage.h).
  unsigned gridsInBuffer = 0;

  /// The index of medium m's grid in gridMedia, or -1.
  int gridOf(int m) const {
    for (std::size_t g = 0; g < gridMedia.size(); ++g)
      if (gridMedia[g] == m) return static_cast<int>(g);
    return -1;
  }

  std::vector<std::string> defines() const {
    std::vector<std::string> out = {"PREVIEW_MEDIA " + std::to_string(count)};
    if (gridMedia.empty()) return out;
    std::string media;
    for (int m : gridMedia) media += (media.empty() ? "" : ", ") + std::to_string(m);
    out.push_back("PREVIEW_MEDIA_GRIDS " + std::to_string(gridMedia.size()));
    out.push_back("PREVIEW_MEDIA_GRID_MEDIA " + media);
    if (gridsInBuffer != 0) out.push_back("PREVIEW_MEDIA_GRID_NANOVDB " + std::to_string(gridsInBuffer));
    return out;
  }
  bool operator==(const MediaShaderLayout&) const = default;
};

}  // namespace vplab
