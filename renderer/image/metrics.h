#pragma once
// Error of an image I against a reference R (docs/theory.md §10): RMSE, relMSE = mean((I-R)^2 / (R^2 + 0.01)) over pixels
// and channels, and the energy ratio mean(I)/mean(R) (clamping shows as < 1). Plus the counts that explain a bad
// number: NaN/Inf pixels and negative pixels.

#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

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

/// Per-pixel relative error of the luminance, |L(I) - L(R)| / L(R), over the pixels where L(R) > 0: how closely an
/// approximation of a sum (lightcuts, matrix row-column sampling) matches the exact sum of the same terms pixel by
/// pixel. energyRatio = sum L(I) / sum L(R) over every pixel. Throws std::invalid_argument on a size mismatch.
struct PixelRelativeError {
  double mean = 0.0;
  double p95 = 0.0;  ///< 95th percentile
  double energyRatio = 0.0;
  std::size_t pixels = 0;  ///< pixels with L(R) > 0
};
PixelRelativeError pixelRelativeError(const Image& image, const Image& reference);

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

/// Pixels a comparison leaves out (row-major like Image, 1 = left out). The emitters' mask (emitterMask in
/// renderer/offline/emitter_mask.h) is the usual one: a visible emitter is so much brighter than the lit surfaces
/// that it dominates an image's sum, so a mean ratio over all pixels hides a 5 % error on every lit surface.
struct PixelMask {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> excluded;

  PixelMask() = default;
  PixelMask(int w, int h) : width(w), height(h), excluded(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0) {}
  uint8_t& at(int x, int y) { return excluded[static_cast<std::size_t>(y) * width + x]; }
  uint8_t at(int x, int y) const { return excluded[static_cast<std::size_t>(y) * width + x]; }
  std::size_t count() const;
};

/// The mask grown by `radius` pixels in each direction (a 3x3 neighbourhood for radius 1): pixels at an emitter's
/// edge mix emitter and surface, and filters (downscaling, deinterleaving) spread the emitter into them.
PixelMask dilateMask(const PixelMask& mask, int radius);

/// The mask for blockAverage(image, block): a block is left out when any of its pixels is.
PixelMask blockMask(const PixelMask& mask, int block);

/// compareImages over the pixels the mask keeps; throws std::invalid_argument when the three sizes differ.
ImageMetrics compareImagesExcluding(const Image& image, const Image& reference, const PixelMask& excluded);

/// mean(image) / mean(reference) (channel sums, as ImageMetrics::energyRatioOverall) over the pixels that are not
/// emitters nor their edges: the energy check of every image test. `emitters` is emitterMask's (already dilated).
double meanRatioExcludingEmitters(const Image& image, const Image& reference, const PixelMask& emitters);

/// The image times 1 / (its mean luminance over the pixels the mask keeps), so that relMSE's +0.01 in the
/// denominator weighs errors alike on dim and bright images (an indirect image of mean 0.03 would otherwise admit a
/// uniform 33 % error at relMSE 0.01). Scale both images by the reference's factor: unitMeanScale(reference, mask).
double unitMeanScale(const Image& reference, const PixelMask& excluded);
Image scaled(const Image& image, double factor);

/// Mean Rec. 709 luminance over the pixels the mask keeps (0 when it keeps none).
double meanLuminanceExcluding(const Image& image, const PixelMask& excluded);

/// compareImagesExcluding on both images times unitMeanScale(reference, excluded): relMSE at unit mean over the kept
/// pixels; its energyRatioOverall is meanRatioExcludingEmitters (the scale cancels).
ImageMetrics compareAtUnitMean(const Image& image, const Image& reference, const PixelMask& excluded);

/// True when all three channels are finite.
bool isFinite(glm::vec3 v);

}  // namespace vplab
