#include "renderer/image/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "renderer/core/sampling.h"

namespace vplab {

namespace {

void requireSameSize(const Image& image, const Image& reference) {
  if (image.width != reference.width || image.height != reference.height)
    throw std::invalid_argument("image size " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                                " differs from reference size " + std::to_string(reference.width) + "x" +
                                std::to_string(reference.height));
}

bool anyNegative(glm::vec3 v) {
  return v.x < 0.0f || v.y < 0.0f || v.z < 0.0f;
}

double ratio(double numerator, double denominator) {
  if (denominator != 0.0) return numerator / denominator;
  return numerator == 0.0 ? 1.0 : std::numeric_limits<double>::infinity();
}

}  // namespace

bool isFinite(glm::vec3 v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

double meanLuminance(const Image& image) {
  double sum = 0.0;
  for (const glm::vec3& p : image.pixels) sum += luminance(p);
  return image.empty() ? 0.0 : sum / static_cast<double>(image.size());
}

PixelRelativeError pixelRelativeError(const Image& image, const Image& reference) {
  if (image.width != reference.width || image.height != reference.height)
    throw std::invalid_argument("pixelRelativeError: image sizes differ");
  std::vector<double> relative;
  double sumImage = 0.0, sumReference = 0.0;
  for (std::size_t i = 0; i < reference.pixels.size(); ++i) {
    const double r = luminance(reference.pixels[i]), v = luminance(image.pixels[i]);
    sumImage += v, sumReference += r;
    if (r > 0.0) relative.push_back(std::abs(v - r) / r);
  }
  PixelRelativeError e;
  e.pixels = relative.size();
  e.energyRatio = sumReference > 0.0 ? sumImage / sumReference : 0.0;
  if (relative.empty()) return e;
  for (double r : relative) e.mean += r;
  e.mean /= static_cast<double>(relative.size());
  const std::size_t at = std::min(relative.size() - 1, static_cast<std::size_t>(0.95 * relative.size()));
  std::nth_element(relative.begin(), relative.begin() + static_cast<std::ptrdiff_t>(at), relative.end());
  e.p95 = relative[at];
  return e;
}

ImageMetrics compareImages(const Image& image, const Image& reference) {
  return compareImagesExcluding(image, reference, PixelMask(image.width, image.height));
}

ImageMetrics compareImagesExcluding(const Image& image, const Image& reference, const PixelMask& excluded) {
  requireSameSize(image, reference);
  if (excluded.width != image.width || excluded.height != image.height)
    throw std::invalid_argument("mask size " + std::to_string(excluded.width) + "x" + std::to_string(excluded.height) +
                                " differs from image size " + std::to_string(image.width) + "x" +
                                std::to_string(image.height));
  ImageMetrics m;
  // Sums in double: a 1080p image has 6M terms, and float accumulation would lose the small relMSE contributions.
  double squared = 0.0, relative = 0.0;
  glm::dvec3 sumImage(0.0), sumReference(0.0);
  for (std::size_t i = 0; i < image.size(); ++i) {
    if (excluded.excluded[i]) continue;
    glm::vec3 a = image.pixels[i], r = reference.pixels[i];
    bool finiteA = isFinite(a), finiteR = isFinite(r);
    if (!finiteA) ++m.nonFinitePixels;
    if (!finiteR) ++m.nonFiniteReferencePixels;
    if (finiteA && anyNegative(a)) ++m.negativePixels;
    if (finiteR && anyNegative(r)) ++m.negativeReferencePixels;
    if (!finiteA || !finiteR) continue;
    ++m.comparedPixels;
    for (int c = 0; c < 3; ++c) {
      double d = static_cast<double>(a[c]) - static_cast<double>(r[c]);
      double rc = r[c];
      squared += d * d;
      relative += d * d / (rc * rc + kRelMseEpsilon);
    }
    sumImage += glm::dvec3(a);
    sumReference += glm::dvec3(r);
  }
  if (m.comparedPixels == 0) return m;
  double n = static_cast<double>(m.comparedPixels);
  m.rmse = std::sqrt(squared / (3.0 * n));
  m.relMse = relative / (3.0 * n);
  m.meanImage = sumImage / n;
  m.meanReference = sumReference / n;
  for (int c = 0; c < 3; ++c) m.energyRatio[c] = ratio(m.meanImage[c], m.meanReference[c]);
  m.energyRatioOverall =
      ratio(m.meanImage.x + m.meanImage.y + m.meanImage.z, m.meanReference.x + m.meanReference.y + m.meanReference.z);
  return m;
}

double meanRatioExcludingEmitters(const Image& image, const Image& reference, const PixelMask& emitters) {
  return compareImagesExcluding(image, reference, emitters).energyRatioOverall;
}

std::size_t PixelMask::count() const {
  std::size_t n = 0;
  for (uint8_t e : excluded) n += e != 0;
  return n;
}

PixelMask dilateMask(const PixelMask& mask, int radius) {
  PixelMask out(mask.width, mask.height);
  for (int y = 0; y < mask.height; ++y)
    for (int x = 0; x < mask.width; ++x) {
      if (!mask.at(x, y)) continue;
      for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) {
          int nx = x + dx, ny = y + dy;
          if (nx >= 0 && ny >= 0 && nx < mask.width && ny < mask.height) out.at(nx, ny) = 1;
        }
    }
  return out;
}

PixelMask blockMask(const PixelMask& mask, int block) {
  if (block < 1) throw std::invalid_argument("blockMask: block must be >= 1");
  PixelMask out((mask.width + block - 1) / block, (mask.height + block - 1) / block);
  for (int y = 0; y < mask.height; ++y)
    for (int x = 0; x < mask.width; ++x)
      if (mask.at(x, y)) out.at(x / block, y / block) = 1;
  return out;
}

double meanLuminanceExcluding(const Image& image, const PixelMask& excluded) {
  return luminance(glm::vec3(compareImagesExcluding(image, image, excluded).meanImage));
}

double unitMeanScale(const Image& reference, const PixelMask& excluded) {
  const double mean = meanLuminanceExcluding(reference, excluded);
  return mean > 0.0 ? 1.0 / mean : 1.0;
}

Image scaled(const Image& image, double factor) {
  Image out = image;
  for (glm::vec3& p : out.pixels) p *= static_cast<float>(factor);
  return out;
}

ImageMetrics compareAtUnitMean(const Image& image, const Image& reference, const PixelMask& excluded) {
  const double toUnitMean = unitMeanScale(reference, excluded);
  return compareImagesExcluding(scaled(image, toUnitMean), scaled(reference, toUnitMean), excluded);
}

Image relativeErrorImage(const Image& image, const Image& reference) {
  requireSameSize(image, reference);
  Image out(image.width, image.height);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t i = 0; i < image.size(); ++i) {
    glm::vec3 a = image.pixels[i], r = reference.pixels[i];
    if (!isFinite(a) || !isFinite(r)) {
      out.pixels[i] = glm::vec3(nan);
      continue;
    }
    glm::vec3 d = a - r;
    out.pixels[i] = d * d / (r * r + static_cast<float>(kRelMseEpsilon));
  }
  return out;
}

Image signedDifferenceImage(const Image& image, const Image& reference) {
  requireSameSize(image, reference);
  Image out(image.width, image.height);
  // Non-finite inputs propagate as NaN/Inf on their own, which the heatmap marks.
  for (std::size_t i = 0; i < image.size(); ++i) out.pixels[i] = image.pixels[i] - reference.pixels[i];
  return out;
}

Image blockAverage(const Image& image, int block) {
  if (block < 1) throw std::invalid_argument("blockAverage: block must be >= 1");
  Image out((image.width + block - 1) / block, (image.height + block - 1) / block);
  for (int by = 0; by < out.height; ++by)
    for (int bx = 0; bx < out.width; ++bx) {
      glm::dvec3 sum(0.0);
      int n = 0;
      for (int y = by * block; y < std::min(image.height, (by + 1) * block); ++y)
        for (int x = bx * block; x < std::min(image.width, (bx + 1) * block); ++x) {
          sum += glm::dvec3(image.at(x, y));
          ++n;
        }
      out.at(bx, by) = glm::vec3(sum / static_cast<double>(std::max(n, 1)));
    }
  return out;
}

}  // namespace vplab
