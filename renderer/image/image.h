#pragma once
// Linear float RGB images: what every pass produces and every metric compares. Tonemapping happens only when an
// image is shown or written as PNG.

#include <glm/glm.hpp>

#include <cstddef>
#include <vector>

namespace vplab {

struct Image {
  int width = 0;
  int height = 0;
  std::vector<glm::vec3> pixels;  ///< row-major, row 0 at the top of the picture, linear radiance

  Image() = default;
  Image(int w, int h, glm::vec3 fill = glm::vec3(0.0f))
      : width(w), height(h), pixels(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), fill) {}

  bool empty() const { return pixels.empty(); }
  std::size_t size() const { return pixels.size(); }
  glm::vec3& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
  const glm::vec3& at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

/// `image` resampled to width x height by bilinear interpolation between pixel centres (edges clamped): a coarse
/// image shown at the size of the one it stands in for.
Image resizedBilinear(const Image& image, int width, int height);

}  // namespace vplab
