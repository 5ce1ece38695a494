#pragma once
// Error of an image I against a reference R (docs/theory.md §10): RMSE, relMSE = mean((I-R)^2 / (R^2 + 0.01)) over pixels
// and channels, and the energy ratio mean(I)/mean(R) (clamping shows as < 1). Plus the counts that explain a bad
// number: NaN/Inf pixels and negative pixels.

#include <cstddef>
#include <glm/glm.hpp>

#include "renderer/image/image.h"

namespace vplab {

/// The 0.01 in relMSE's denominator keeps black reference pixels from dominating the mean.
inline constexpr double kRelMseEpsilon = 0.01;

struct ImageMetrics {
  /// Pixels where both I and R are finite in all three channels; every error and mean below is over these only,
  /// so one NaN does not turn the whole comparison into NaN (it is counted instead).
  std::size_t comparedPixels = 0;
  double rmse = 0.0;    ///< sqrt(mean over pixels and channels of (I-R)^2), in radiance units
  double relMse = 0.0;  ///< mean over pixels and channels of (I-R)^2 / (R^2 + 0.01), unitless
  /// mean(I_c)/mean(R_c) per channel; 1 when both means are 0, +inf when only the reference mean is 0.
  glm::dvec3 energyRatio{1.0};
  double energyRatioOverall = 1.0;           ///< (sum of the channel means of I) / (same for R), same conventions
  glm::dvec3 meanImage{0.0};                 ///< per-channel mean of I
  glm::dvec3 meanReference{0.0};             ///< per-channel mean of R
  std::size_t nonFinitePixels = 0;           ///< pixels of I with a NaN or Inf in any channel
  std::size_t nonFiniteReferencePixels = 0;  ///< same for R
  std::size_t negativePixels = 0;            ///< finite pixels of I with any channel < 0
  std::size_t negativeReferencePixels = 0;   ///< same for R
};

/// Compares image against reference; throws std::invalid_argument when the sizes differ.
ImageMetrics compareImages(const Image& image, const Image& reference);

/// Mean Rec. 709 luminance over the pixels (0 for an empty image).
double meanLuminance(const Image& image);

/// Per pixel and channel (I-R)^2 / (R^2 + 0.01): its mean over finite pixels is relMSE. NaN where either is not
/// finite, so heatmaps can mark those pixels. Throws std::invalid_argument on a size mismatch.
Image relativeErrorImage(const Image& image, const Image& reference);

/// Per pixel and channel I - R (positive: too bright). Throws std::invalid_argument on a size mismatch.
Image signedDifferenceImage(const Image& image, const Image& reference);

/// The image averaged over blocks of block x block pixels (partial blocks at the right and bottom edges average
/// what they hold). Comparing block averages measures an estimator's error at the scale of features rather than
/// its per-pixel noise: the "4x4-block relMSE" of docs/methods.md is compareImages(blockAverage(I, 4),
/// blockAverage(R, 4)).relMse. block must be >= 1.
Image blockAverage(const Image& image, int block);

/// True when all three channels are finite.
bool isFinite(glm::vec3 v);

}  // namespace vplab
