#include "renderer/image/tonemap.h"

#include <algorithm>
#include <cmath>

namespace vplab {

float srgbFromLinear(float linear) {
  float v = std::clamp(linear, 0.0f, 1.0f);
  // IEC 61966-2-1: a linear toe below 0.0031308 avoids the infinite slope of the power law at 0.
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

float linearFromSrgb(float encoded) {
  float v = std::clamp(encoded, 0.0f, 1.0f);
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

glm::vec3 srgbFromLinear(glm::vec3 linear) {
  return {srgbFromLinear(linear.x), srgbFromLinear(linear.y), srgbFromLinear(linear.z)};
}

glm::vec3 linearFromSrgb(glm::vec3 encoded) {
  return {linearFromSrgb(encoded.x), linearFromSrgb(encoded.y), linearFromSrgb(encoded.z)};
}

float exposureScale(float stops) {
  return std::exp2(stops);
}

std::uint8_t quantize8(float encoded) {
  // std::clamp lets NaN through; callers map non-finite pixels to magenta before they get here.
  float v = std::clamp(encoded, 0.0f, 1.0f);
  return static_cast<std::uint8_t>(std::lround(v * 255.0f));
}

Rgb8 tonemapPixel(glm::vec3 linear, float stops) {
  if (!std::isfinite(linear.x) || !std::isfinite(linear.y) || !std::isfinite(linear.z)) return kNonFiniteRgb8;
  glm::vec3 encoded = srgbFromLinear(linear * exposureScale(stops));
  return {quantize8(encoded.x), quantize8(encoded.y), quantize8(encoded.z)};
}

std::vector<std::uint8_t> tonemapToRgb8(const Image& image, float stops) {
  std::vector<std::uint8_t> rgb(image.size() * 3);
  for (std::size_t i = 0; i < image.size(); ++i) {
    Rgb8 p = tonemapPixel(image.pixels[i], stops);
    rgb[3 * i + 0] = p[0];
    rgb[3 * i + 1] = p[1];
    rgb[3 * i + 2] = p[2];
  }
  return rgb;
}

}  // namespace vplab
