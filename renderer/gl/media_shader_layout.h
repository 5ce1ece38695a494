#pragma once
// What the passes that read the media table (shaders/common/medium.glsl) are compiled for: the number of media, and
// which of them, if any, carries a density grid. Both are shader defines, so that the loops over the media unroll and
// a scene without a grid compiles exactly the homogeneous code it always had (renderer/gl/media_pass.h uploads the
// table and the grid's texture).

#include <string>
#include <vector>

namespace vplab {

struct MediaShaderLayout {
  int count = 0;        ///< PREVIEW_MEDIA: media in the table (0: none, the transmittance is 1)
  int gridMedium = -1;  ///< PREVIEW_MEDIA_GRID: the table index of the medium with a density grid; -1: none

  std::vector<std::string> defines() const {
    std::vector<std::string> out = {"PREVIEW_MEDIA " + std::to_string(count)};
    if (gridMedium >= 0) out.push_back("PREVIEW_MEDIA_GRID " + std::to_string(gridMedium));
    return out;
  }
  bool operator==(const MediaShaderLayout&) const = default;
};

}  // namespace vplab
