#pragma once
// Display transforms shared by PNG output, heatmaps and (later) the GL tonemap pass: exposure in stops, clamp to
// [0, 1], then the sRGB transfer function of IEC 61966-2-1. Images stay linear everywhere else.

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "renderer/image/image.h"

namespace vplab {

using Rgb8 = std::array<std::uint8_t, 3>;

/// What a NaN or infinite pixel becomes on a display: magenta, so it cannot pass for dark or bright radiance.
inline constexpr Rgb8 kNonFiniteRgb8 = {255, 0, 255};

/// Linear [0, 1] -> sRGB-encoded [0, 1]; the input is clamped first.
float srgbFromLinear(float linear);
/// sRGB-encoded [0, 1] -> linear [0, 1]; the input is clamped first. Inverse of srgbFromLinear.
float linearFromSrgb(float encoded);
glm::vec3 srgbFromLinear(glm::vec3 linear);
glm::vec3 linearFromSrgb(glm::vec3 encoded);

/// Multiplier for an exposure given in photographic stops (each stop doubles the radiance).
float exposureScale(float stops);

/// Rounds an encoded [0, 1] value to 8 bits (the input is clamped).
std::uint8_t quantize8(float encoded);

/// One pixel as shown: linear radiance scaled by 2^stops, clamped, sRGB-encoded, 8 bits. Non-finite -> magenta.
Rgb8 tonemapPixel(glm::vec3 linear, float stops);
/// The whole image as packed 8-bit RGB rows, top row first (the layout PNG writers and GL textures expect).
std::vector<std::uint8_t> tonemapToRgb8(const Image& image, float stops);

}  // namespace vplab
