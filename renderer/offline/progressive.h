#pragma once
// Progressive rendering over all cores, shared by the reference and every CPU VPL method: each pass adds samples to
// every pixel, the running mean can be shown after any pass, and the result does not depend on the thread count
// because each sample draws its random numbers from a stream keyed by (seed, pixel, sample index).

#include "renderer/core/parallel.h"
#include "renderer/core/sampling.h"
#include "renderer/image/image.h"
#include "renderer/scene/scene.h"
#include "renderer/settings.h"

#include <functional>

namespace vplab {

/// Radiance estimate for one camera sample through pixel (x, y); rng is private to this (pixel, sample).
using PixelEstimator = std::function<glm::vec3(int x, int y, uint32_t sampleIndex, Rng& rng)>;

struct ProgressiveOptions {
  int width = 0;
  int height = 0;
  int samplesPerPixel = 1;
  uint32_t seed = 1;
  int threads = 0;          ///< 0 = all cores
  int samplesPerPass = 1;   ///< samples added to every pixel per pass
  /// Called after each pass with the running mean and the samples per pixel so far (from the calling thread).
  std::function<void(const Image& mean, int samplesSoFar)> onPass;
};

struct ProgressiveResult {
  Image image;             ///< mean of the samples taken
  int samplesPerPixel = 0; ///< samples actually taken (fewer when cancelled)
  double seconds = 0.0;
  bool cancelled = false;
  /// Samples whose estimate had a NaN or infinite channel, over the passes taken. They are left out of their pixel's
  /// mean (which averages the pixel's finite samples) and every caller reports the count: any is a defect of an
  /// estimator, never a property of the scene.
  uint64_t nonFiniteSamples = 0;
};

/// The image size, samples per pixel, seed and thread count of `settings`, with the given pass size and callback.
ProgressiveOptions progressiveOptions(const Settings& settings, int samplesPerPass,
                                      std::function<void(const Image& mean, int samplesSoFar)> onPass);

/// Runs the estimator samplesPerPixel times per pixel. Non-finite samples are left out of the mean and counted
/// (ProgressiveResult::nonFiniteSamples); a cancelled render returns the passes completed so far.
ProgressiveResult renderProgressive(const ProgressiveOptions& options, const PixelEstimator& estimator,
                                    RenderControl* control = nullptr);

/// A rectangle of pixels [x0, x1) x [y0, y1), the work item of a tiled render; `index` numbers it in row-major
/// order over the image's tiles.
struct PixelTile {
  uint64_t index = 0;
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  int width() const { return x1 - x0; }
  std::size_t pixelCount() const { return static_cast<std::size_t>(x1 - x0) * (y1 - y0); }
  /// Row-major position of pixel (x, y) inside the tile.
  std::size_t local(int x, int y) const { return static_cast<std::size_t>(y - y0) * (x1 - x0) + (x - x0); }
};

/// One camera sample for every pixel of a tile at once, for estimators that share work among neighbouring pixels:
/// rngs[i] is private to the tile's pixel i (row-major) and this sample, the same stream a PixelEstimator gets for it;
/// out[i] receives that pixel's estimate.
using TileEstimator = std::function<void(const PixelTile& tile, uint32_t sampleIndex, Rng* rngs, glm::vec3* out)>;

/// renderProgressive over square tiles of tileSize pixels (smaller at the right and bottom edges), one tile per work
/// item: the image does not depend on the thread count either.
ProgressiveResult renderProgressiveTiles(const ProgressiveOptions& options, int tileSize,
                                         const TileEstimator& estimator, RenderControl* control = nullptr);

/// Primary ray direction through a film position (x, y) in pixels, (0,0) the top-left corner of the image.
glm::vec3 cameraRayDirection(const Camera& camera, float x, float y, int width, int height);

}  // namespace vplab
