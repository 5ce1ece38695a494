// Local virtual lights (docs/theory.md §21, renderer/offline/lvl_renderer.h): a tile of one pixel is Kollig-Keller's
// compensation, no bound is the VPL render, the expected image depends neither on the bound nor on the tile size,
// and it matches the path-traced reference on the bundled glossy scene.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "renderer/image/metrics.h"
#include "renderer/offline/emitter_mask.h"
#include "renderer/offline/lvl_renderer.h"
#include "renderer/offline/path_tracer.h"
#include "renderer/offline/vpl_renderer.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/vpl/vpl_generation.h"
#include "tests/test_scenes.h"

namespace vplab {
namespace {

bool sameBits(const Image& a, const Image& b) {
  return a.pixels.size() == b.pixels.size() &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(glm::vec3)) == 0;
}

double meanOf(const Image& image) {
  double sum = 0.0;
  for (const glm::vec3& p : image.pixels) sum += static_cast<double>(p.r) + p.g + p.b;
  return sum / (3.0 * static_cast<double>(image.pixels.size()));
}

/// sqrt(mean squared difference) / mean(b), over all channels.
double relativeRmse(const Image& a, const Image& b) {
  double sum = 0.0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    const glm::vec3 d = a.pixels[i] - b.pixels[i];
    sum += static_cast<double>(glm::dot(d, d));
  }
  return std::sqrt(sum / (3.0 * static_cast<double>(a.pixels.size()))) / meanOf(b);
}

// A tile of one pixel with one local light draws exactly Kollig-Keller's random numbers and computes its estimate
// f (1 - b/G) cos L_r / p through the mixture pdf: the images agree to float rounding, with the same shadow rays.
TEST(Lvl, TileOfOnePixelIsKolligKeller) {
  for (const char* name : {"cornell-glossy", "glossy-counter"}) {
    auto scene = test::loadAssetScene(name);
    Settings s = test::smallVplSettings(32, 64);
    s.samplesPerPixel = 2;
    s.clampBound = 4.0f;
    s.lvlTileSize = 1;
    s.lvlLightsPerTile = 1;
    const VplSet vpls = generateVpls(*scene, s);
    const VplRenderResult kk = renderVpl(*scene, vpls, Method::VplKK, s);
    const VplRenderResult lvl = renderLvl(*scene, vpls, s);
    const VplRenderResult bounded = renderVpl(*scene, vpls, Method::Vpl, s);
    EXPECT_LT(relativeRmse(lvl.image, kk.image), 1e-5) << name;
    EXPECT_EQ(lvl.shadowRays, kk.shadowRays) << name;
    // The residual is there to be matched: the compensation adds a visible share to the bounded image.
    EXPECT_GT(meanOf(kk.image) / meanOf(bounded.image), 1.01) << name;
  }
}

// No bound, no residual: the global VPLs alone, the VPL render's camera samples bit for bit.
TEST(Lvl, InfiniteBoundIsTheVplRender) {
  auto scene = test::loadAssetScene("glossy-counter");
  Settings s = test::smallVplSettings(32, 64);
  const VplSet vpls = generateVpls(*scene, s);
  EXPECT_TRUE(sameBits(renderLvl(*scene, vpls, s).image, renderVpl(*scene, vpls, Method::Vpl, s).image));
}

// Tiles are the work items and their random numbers are keyed by (seed, pixel or tile, sample).
TEST(Lvl, SameImageAtAnyThreadCount) {
  auto scene = test::loadAssetScene("glossy-counter");
  Settings s = test::smallVplSettings(32, 64);
  s.clampBound = 10.0f;
  s.lvlTileSize = 5;  // tiles cut at the image's edges too
  const VplSet vpls = generateVpls(*scene, s);
  s.threads = 1;
  const Image one = renderLvl(*scene, vpls, s).image;
  s.threads = 3;
  EXPECT_TRUE(sameBits(one, renderLvl(*scene, vpls, s).image));
}

TEST(Lvl, ScenesWithMediaAreRefused) {
  auto scene = test::loadAssetScene("cornell-fog");
  Settings s = test::smallVplSettings(8, 8);
  s.clampBound = 10.0f;
  EXPECT_THROW(renderLvl(*scene, generateVpls(*scene, s), s), SceneError);
}

/// Mean indirect image of lvl over `seeds` pixel seeds with one VPL set.
double meanOverPixelSeeds(const OfflineScene& scene, const VplSet& vpls, Settings s, int seeds) {
  double sum = 0.0;
  for (int i = 0; i < seeds; ++i) {
    s.seed = 500 + static_cast<uint32_t>(i);
    sum += meanOf(renderLvl(scene, vpls, s).image);
  }
  return sum / seeds;
}

// With one VPL set and one bound, the tile size and the local lights per tile only change how the residual is
// sampled (the balance heuristic over the group's pixels), not what it converges to; the glossy counter's local
// lights on the metal re-evaluate their incident samples toward the other pixels of their group.
TEST(Lvl, TileSizeDoesNotChangeTheExpectedImage) {
  auto scene = test::loadAssetScene("glossy-counter");
  Settings s = test::smallVplSettings(32, 128);
  s.components = Components::Indirect;
  s.clampBound = 2.0f;
  s.samplesPerPixel = 4;
  const VplSet vpls = generateVpls(*scene, s);
  const double bounded = meanOf(renderVpl(*scene, vpls, Method::Vpl, s).image);
  s.lvlTileSize = 1;
  s.lvlLightsPerTile = 1;
  const double single = meanOverPixelSeeds(*scene, vpls, s, 4);
  for (auto [tile, lights] : {std::pair{4, 8}, std::pair{8, 16}, std::pair{16, 32}}) {
    s.lvlTileSize = tile;
    s.lvlLightsPerTile = lights;
    const double tiled = meanOverPixelSeeds(*scene, vpls, s, 4);
    std::printf("tile %d, %d lights: mean %.5f, tile 1: %.5f (residual %.5f)\n", tile, lights, tiled, single,
                single - bounded);
    EXPECT_NEAR(tiled / single, 1.0, 0.01) << "tile " << tile;
  }
  EXPECT_GT(single / bounded, 1.05);  // the residual is a visible share
}

// On the glossy counter, the indirect light (Components::Indirect: what the VPLs, the bound and the local lights
// change; the direct light, the same estimator in every method, would dilute an error in it) against the path-traced
// reference's (emitters and their edges left out), averaged over VPL sets. The spread between VPL sets is large on
// the metal counter (a VPL on a wall seen in the counter's GGX lobe is a rare, large contribution that no bound on G
// removes), so the test takes many small renders, each bound its own sets. Measured (16 sets of 4096 VPLs at 16^2 per
// bound): b = 20 0.9885, b = 5 0.9924, b = 1 0.9810 (standard errors 1.7, 1.3, 1.6 %), all bounds 0.9873 (standard
// error 0.9 %). Bounds: each bound within 4.5 % (about 3 standard errors), all bounds within 2.5 % (2.8), below the
// 5 % of an error in the indirect light, which fails the latter (checked: the lvl image times 1.05 or 0.95).
TEST(Lvl, GlossyCounterMatchesTheReferenceAtAnyBound) {
  auto scene = test::loadAssetScene("glossy-counter");
  const int size = 16;
  Settings r = test::smallReferenceSettings(size, 8192);
  r.components = Components::Indirect;
  const Image reference = renderReference(*scene, r).image;
  const PixelMask emitters = emitterMask(scene->embree(), size, size);
  const int seeds = 16;
  const std::vector<float> bounds = {20.0f, 5.0f, 1.0f};
  double total = 0.0;
  for (std::size_t b = 0; b < bounds.size(); ++b) {
    double sum = 0.0, sumSquares = 0.0;
    for (int i = 0; i < seeds; ++i) {
      Settings s = test::smallVplSettings(size, 4096);
      s.seed = 70 + 100 * static_cast<uint32_t>(b) + static_cast<uint32_t>(i);
      s.clampBound = bounds[b];
      s.lvlTileSize = 4;
      s.components = Components::Indirect;
      const double q =
          meanRatioExcludingEmitters(renderLvl(*scene, generateVpls(*scene, s), s).image, reference, emitters);
      sum += q;
      sumSquares += q * q;
    }
    const double mean = sum / seeds;
    const double standardError = std::sqrt((sumSquares / seeds - mean * mean) / (seeds - 1));
    std::printf("[ measured ] b = %g: lvl / reference %.4f (standard error %.4f over %d VPL sets)\n", bounds[b], mean,
                standardError, seeds);
    EXPECT_NEAR(mean, 1.0, 0.045) << "b = " << bounds[b];
    total += mean / static_cast<double>(bounds.size());
  }
  std::printf("[ measured ] all bounds: lvl / reference %.4f\n", total);
  EXPECT_NEAR(total, 1.0, 0.025);
}

}  // namespace
}  // namespace vplab
