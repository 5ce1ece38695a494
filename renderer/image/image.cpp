#include "renderer/image/image.h"

#include <algorithm>

namespace vplab {

Image resizedBilinear(const Image& image, int width, int height) {
  Image out(width, height);
  if (image.empty() || width <= 0 || height <= 0) return out;
  const float sx = static_cast<float>(image.width) / static_cast<float>(width);
  const float sy = static_cast<float>(image.height) / static_cast<float>(height);
  for (int y = 0; y < height; ++y) {
    // The source position of this pixel's centre, in source pixel-centre coordinates.
    const float v = std::clamp((static_cast<float>(y) + 0.5f) * sy - 0.5f, 0.0f, static_cast<float>(image.height - 1));
    const int y0 = static_cast<int>(v), y1 = std::min(y0 + 1, image.height - 1);
    const float fy = v - static_cast<float>(y0);
    for (int x = 0; x < width; ++x) {
      const float u =
          std::clamp((static_cast<float>(x) + 0.5f) * sx - 0.5f, 0.0f, static_cast<float>(image.width - 1));
      const int x0 = static_cast<int>(u), x1 = std::min(x0 + 1, image.width - 1);
      const float fx = u - static_cast<float>(x0);
      const glm::vec3 top = glm::mix(image.at(x0, y0), image.at(x1, y0), fx);
      const glm::vec3 bottom = glm::mix(image.at(x0, y1), image.at(x1, y1), fx);
      out.at(x, y) = glm::mix(top, bottom, fy);
    }
  }
  return out;
}

}  // namespace vplab
