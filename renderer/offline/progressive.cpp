#include "renderer/offline/progressive.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <utility>

namespace vplab {

glm::vec3 cameraRayDirection(const Camera& camera, float x, float y, int width, int height) {
  glm::vec2 ndc(2.0f * x / static_cast<float>(width) - 1.0f, 1.0f - 2.0f * y / static_cast<float>(height));
  return camera.rayDirection(ndc, static_cast<float>(width) / static_cast<float>(height));
}

ProgressiveOptions progressiveOptions(const Settings& settings, int samplesPerPass,
                                      std::function<void(const Image& mean, int samplesSoFar)> onPass) {
  ProgressiveOptions options;
  options.width = settings.width;
  options.height = settings.height;
  options.samplesPerPixel = settings.samplesPerPixel;
  options.seed = settings.seed;
  options.threads = settings.threads;
  options.samplesPerPass = samplesPerPass;
  options.onPass = std::move(onPass);
  return options;
}

namespace {

/// One pass's work on one item (a row or a tile): `count` samples from sample index `first` for each of the item's
/// pixels, their finite sum and count written to passSum and passFinite at the pixel's index.
using PassItem = std::function<void(int64_t item, int first, int count, std::vector<glm::dvec3>& passSum,
                                    std::vector<uint32_t>& passFinite)>;

ProgressiveResult runPasses(const ProgressiveOptions& o, int64_t items, const PassItem& work, RenderControl* control) {
  auto start = std::chrono::steady_clock::now();
  ProgressiveResult result;
  result.image = Image(o.width, o.height);
  if (o.width <= 0 || o.height <= 0 || o.samplesPerPixel <= 0) return result;

  // Sums in double so that thousands of samples do not lose the low bits; per pixel, the finite samples summed.
  std::vector<glm::dvec3> sum(static_cast<std::size_t>(o.width) * o.height, glm::dvec3(0.0));
  std::vector<uint32_t> finiteCount(sum.size(), 0);
  const int perPass = std::max(1, o.samplesPerPass);
  const int64_t pixels = static_cast<int64_t>(o.width) * o.height;
  const int totalPasses = (o.samplesPerPixel + perPass - 1) / perPass;

  int taken = 0;
  std::vector<glm::dvec3> passSum(sum.size());
  std::vector<uint32_t> passFinite(sum.size());
  // The mean of a pixel's finite samples; black for a pixel none of whose samples was finite.
  auto meanAt = [&](int64_t i) {
    return finiteCount[i] > 0 ? glm::vec3(sum[i] / static_cast<double>(finiteCount[i])) : glm::vec3(0.0f);
  };
  for (int pass = 0; pass < totalPasses; ++pass) {
    const int first = taken;
    const int count = std::min(perPass, o.samplesPerPixel - taken);
    std::atomic<int64_t> itemsDone{0};
    // A pass is added to the running sum only when it completes, so a cancelled render stays an unbiased mean.
    parallelFor(items, o.threads, [&](int64_t item, int) {
      if (control && control->cancelled()) return;
      work(item, first, count, passSum, passFinite);
      int64_t done = itemsDone.fetch_add(1) + 1;
      if (control && control->onProgress && (done % 16 == 0 || done == items))
        control->onProgress((static_cast<float>(pass) + static_cast<float>(done) / items) / totalPasses);
    });
    if (control && control->cancelled()) {
      result.cancelled = true;
      break;
    }
    for (int64_t i = 0; i < pixels; ++i) {
      sum[i] += passSum[i];
      finiteCount[i] += passFinite[i];
      result.nonFiniteSamples += static_cast<uint64_t>(count) - passFinite[i];
    }
    taken += count;
    if (o.onPass) {
      Image mean(o.width, o.height);
      for (int64_t i = 0; i < pixels; ++i) mean.pixels[i] = meanAt(i);
      o.onPass(mean, taken);
    }
  }

  result.samplesPerPixel = taken;
  for (int64_t i = 0; i < pixels; ++i) result.image.pixels[i] = meanAt(i);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

ProgressiveResult renderProgressive(const ProgressiveOptions& o, const PixelEstimator& estimator,
                                    RenderControl* control) {
  // Rows are the work items: big enough to amortise scheduling, small enough to balance two cores.
  auto row = [&](int64_t item, int first, int count, std::vector<glm::dvec3>& passSum,
                 std::vector<uint32_t>& passFinite) {
    const int y = static_cast<int>(item);
    for (int x = 0; x < o.width; ++x) {
      glm::dvec3 acc(0.0);
      uint32_t finiteSamples = 0;
      uint64_t pixelIndex = static_cast<uint64_t>(y) * o.width + x;
      for (int s = first; s < first + count; ++s) {
        Rng rng(hashKey(o.seed, pixelIndex, static_cast<uint64_t>(s)));
        glm::vec3 L = estimator(x, y, static_cast<uint32_t>(s), rng);
        if (finite(L)) {
          acc += glm::dvec3(L);
          ++finiteSamples;
        }
      }
      passSum[pixelIndex] = acc;
      passFinite[pixelIndex] = finiteSamples;
    }
  };
  return runPasses(o, std::max(0, o.height), row, control);
}

ProgressiveResult renderProgressiveTiles(const ProgressiveOptions& o, int tileSize, const TileEstimator& estimator,
                                         RenderControl* control) {
  const int side = std::max(1, tileSize);
  const int64_t tilesX = (std::max(0, o.width) + side - 1) / side;
  const int64_t tilesY = (std::max(0, o.height) + side - 1) / side;
  auto tile = [&](int64_t item, int first, int count, std::vector<glm::dvec3>& passSum,
                  std::vector<uint32_t>& passFinite) {
    PixelTile t;
    t.index = static_cast<uint64_t>(item);
    t.x0 = static_cast<int>(item % tilesX) * side;
    t.y0 = static_cast<int>(item / tilesX) * side;
    t.x1 = std::min(o.width, t.x0 + side);
    t.y1 = std::min(o.height, t.y0 + side);
    const std::size_t n = static_cast<std::size_t>(t.x1 - t.x0) * (t.y1 - t.y0);
    std::vector<Rng> rngs(n);
    std::vector<glm::vec3> out(n);
    std::vector<glm::dvec3> acc(n, glm::dvec3(0.0));
    std::vector<uint32_t> finiteSamples(n, 0);
    for (int s = first; s < first + count; ++s) {
      // The same per-(pixel, sample) streams as renderProgressive: a tile of one pixel draws what a pixel draws.
      for (int y = t.y0; y < t.y1; ++y)
        for (int x = t.x0; x < t.x1; ++x)
          rngs[t.local(x, y)] = Rng(hashKey(o.seed, static_cast<uint64_t>(y) * o.width + x, static_cast<uint64_t>(s)));
      estimator(t, static_cast<uint32_t>(s), rngs.data(), out.data());
      for (std::size_t i = 0; i < n; ++i)
        if (finite(out[i])) {
          acc[i] += glm::dvec3(out[i]);
          ++finiteSamples[i];
        }
    }
    for (int y = t.y0; y < t.y1; ++y)
      for (int x = t.x0; x < t.x1; ++x) {
        const std::size_t pixelIndex = static_cast<std::size_t>(y) * o.width + x;
        passSum[pixelIndex] = acc[t.local(x, y)];
        passFinite[pixelIndex] = finiteSamples[t.local(x, y)];
      }
  };
  return runPasses(o, tilesX * tilesY, tile, control);
}

}  // namespace vplab
