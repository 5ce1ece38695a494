#include "renderer/image/tonemap.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>

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

// thresholds[k - 1]: the smallest float v with quantize8(srgbFromLinear(v)) >= k, found once by bisection over the
// bit patterns of the floats in [0, 1] (ordered as their values) with those same functions. The 8-bit value of v is
// then the number of thresholds at or below it: the same byte as the pow per channel. To find it without a search
// whose branches a real image's pixels mispredict, the floats in [0, 1] are split into buckets by their top 16 bits
// (exponent and 7 bits of mantissa): a bucket's byte is its smallest float's, plus one if v is at or above the next
// threshold. A bucket spans 2^-7 of its value, less than a byte's step anywhere in [0, 1] (0.9 % at 1), so no bucket
// holds two thresholds (Tonemap.ThresholdSearchGivesTheFormulasBytes checks the floats around every one). A 640x480
// image of noise takes 2.1 ms, against 9.5 for a binary search over the thresholds (a branch per step).
struct Encoder {
  std::array<float, 256> thresholds;  // the last one above 1: never reached
  std::array<std::uint8_t, (std::bit_cast<std::uint32_t>(1.0f) >> 16) + 1> bucketByte;
};

const Encoder& encoder() {
  static const Encoder e = [] {
    Encoder e{};
    for (int k = 1; k <= 255; ++k) {
      std::uint32_t below = 0, atOrAbove = std::bit_cast<std::uint32_t>(1.0f);
      while (atOrAbove - below > 1) {
        const std::uint32_t mid = below + (atOrAbove - below) / 2;
        (quantize8(srgbFromLinear(std::bit_cast<float>(mid))) >= k ? atOrAbove : below) = mid;
      }
      e.thresholds[static_cast<std::size_t>(k - 1)] = std::bit_cast<float>(atOrAbove);
    }
    e.thresholds[255] = 2.0f;
    int n = 0;
    for (std::size_t b = 0; b < e.bucketByte.size(); ++b) {
      const float smallest = std::bit_cast<float>(static_cast<std::uint32_t>(b) << 16);
      while (e.thresholds[static_cast<std::size_t>(n)] <= smallest) ++n;
      e.bucketByte[b] = static_cast<std::uint8_t>(n);
    }
    return e;
  }();
  return e;
}

// quantize8(srgbFromLinear(v)) for a finite v; selects rather than branches (negative zero becomes 0).
std::uint8_t encode8(float v, const Encoder& e) {
  v = v > 0.0f ? v : 0.0f;
  v = v < 1.0f ? v : 1.0f;
  const int n = e.bucketByte[std::bit_cast<std::uint32_t>(v) >> 16];
  return static_cast<std::uint8_t>(n + (e.thresholds[static_cast<std::size_t>(n)] <= v ? 1 : 0));
}

Rgb8 tonemapScaled(glm::vec3 linear, float scale, const Encoder& e) {
  if (!std::isfinite(linear.x) || !std::isfinite(linear.y) || !std::isfinite(linear.z)) return kNonFiniteRgb8;
  const glm::vec3 v = linear * scale;
  return {encode8(v.x, e), encode8(v.y, e), encode8(v.z, e)};
}

}  // namespace

Rgb8 tonemapPixel(glm::vec3 linear, float stops) {
  return tonemapScaled(linear, exposureScale(stops), encoder());
}

std::vector<std::uint8_t> tonemapToRgb8(const Image& image, float stops) {
  std::vector<std::uint8_t> rgb(image.size() * 3);
  const float scale = exposureScale(stops);
  const Encoder& e = encoder();
  for (std::size_t i = 0; i < image.size(); ++i) {
    Rgb8 p = tonemapScaled(image.pixels[i], scale, e);
    rgb[3 * i + 0] = p[0];
    rgb[3 * i + 1] = p[1];
    rgb[3 * i + 2] = p[2];
  }
  return rgb;
}

}  // namespace vplab
