#include "renderer/image/tonemap.h"

#include <algorithm>
#include <bit>
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

namespace {

// threshold[k - 1]: the smallest float v with quantize8(srgbFromLinear(v)) >= k, found once by bisection over the
// bit patterns of the floats in [0, 1] (ordered as their values) with those same functions. The 8-bit value of v is
// then the number of thresholds at or below it: the same byte as the pow per channel, found by a binary search
// (640x480 tonemapped in about 1 ms instead of 8).
const std::array<float, 255>& encodeThresholds() {
  static const std::array<float, 255> thresholds = [] {
    std::array<float, 255> t{};
    for (int k = 1; k <= 255; ++k) {
      std::uint32_t below = 0, atOrAbove = std::bit_cast<std::uint32_t>(1.0f);
      while (atOrAbove - below > 1) {
        const std::uint32_t mid = below + (atOrAbove - below) / 2;
        (quantize8(srgbFromLinear(std::bit_cast<float>(mid))) >= k ? atOrAbove : below) = mid;
      }
      t[static_cast<std::size_t>(k - 1)] = std::bit_cast<float>(atOrAbove);
    }
    return t;
  }();
  return thresholds;
}

// quantize8(srgbFromLinear(v)) for a finite v.
std::uint8_t encode8(float v, const std::array<float, 255>& thresholds) {
  int n = 0;
  for (int step = 128; step >= 1; step /= 2)
    if (n + step <= 255 && thresholds[static_cast<std::size_t>(n + step - 1)] <= v) n += step;
  return static_cast<std::uint8_t>(n);
}

Rgb8 tonemapScaled(glm::vec3 linear, float scale, const std::array<float, 255>& thresholds) {
  if (!std::isfinite(linear.x) || !std::isfinite(linear.y) || !std::isfinite(linear.z)) return kNonFiniteRgb8;
  const glm::vec3 v = linear * scale;
  return {encode8(v.x, thresholds), encode8(v.y, thresholds), encode8(v.z, thresholds)};
}

}  // namespace

Rgb8 tonemapPixel(glm::vec3 linear, float stops) {
  return tonemapScaled(linear, exposureScale(stops), encodeThresholds());
}

std::vector<std::uint8_t> tonemapToRgb8(const Image& image, float stops) {
  std::vector<std::uint8_t> rgb(image.size() * 3);
  const float scale = exposureScale(stops);
  const std::array<float, 255>& thresholds = encodeThresholds();
  for (std::size_t i = 0; i < image.size(); ++i) {
    Rgb8 p = tonemapScaled(image.pixels[i], scale, thresholds);
    rgb[3 * i + 0] = p[0];
    rgb[3 * i + 1] = p[1];
    rgb[3 * i + 2] = p[2];
  }
  return rgb;
}

}  // namespace vplab
