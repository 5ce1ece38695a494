// Matrix row-column sampling (renderer/offline/mrcs_renderer.h): one cluster per VPL keeps every VPL that lights a row
// with its own flux, a few hundred clusters stay near the exact sum of the same VPLs, and the image does not depend on
// the thread count.

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "renderer/core/sampling.h"
#include "renderer/image/metrics.h"
#include "renderer/offline/mrcs_renderer.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/vpl/vpl_generation.h"
#include "tests/test_scenes.h"

namespace vplab {
namespace {

/// Indirect light, b = 10, `rows` rows and `clusters` clusters.
Settings mrcsSettings(int size, int vpls, int rows, int clusters) {
  Settings s = test::smallVplSettings(size, vpls);
  s.clampBound = 10.0f;
  s.components = Components::Indirect;
  s.mrcsRows = rows;
  s.mrcsClusters = clusters;
  return s;
}

TEST(Mrcs, OneClusterPerVplKeepsEveryLitColumnWithItsOwnFlux) {
  auto box = test::loadAssetScene("cornell-box");
  Settings s = mrcsSettings(16, 400, 256, 1 << 20);  // every pixel a row, every VPL a cluster
  const VplSet vpls = generateVpls(*box, s);
  const MrcsReduction r = reduceVplsByRowColumnSampling(*box, vpls, s);
  EXPECT_EQ(r.rows, 256u);
  ASSERT_EQ(r.reduced.vpls.size() + r.darkColumns, vpls.vpls.size());
  for (std::size_t k = 0; k < r.reduced.vpls.size(); ++k)
    ASSERT_EQ(r.reduced.vpls[k].flux, vpls.vpls[r.representatives[k]].flux);
  // The dark columns light no pixel centre; the images agree but for pixel samples off the centres.
  const double exact = meanLuminance(renderVpl(*box, vpls, Method::Vpl, s).image);
  const double mrcs = meanLuminance(renderMrcs(*box, vpls, s).image);
  EXPECT_NEAR(mrcs / exact, 1.0, 0.01);
}

TEST(Mrcs, AFewHundredClustersStayNearTheExactSum) {
  auto box = test::loadAssetScene("cornell-box");
  Settings s = mrcsSettings(32, 3000, 100, 300);
  const VplSet vpls = generateVpls(*box, s);
  const VplRenderResult exact = renderVpl(*box, vpls, Method::Vpl, s);
  const MrcsRenderResult mrcs = renderMrcs(*box, vpls, s);
  EXPECT_EQ(mrcs.reduction.reduced.vpls.size(), 300u);
  const PixelRelativeError error = pixelRelativeError(mrcs.image, exact.image);
  ASSERT_GT(error.pixels, 500u);
  EXPECT_LT(error.mean, 0.15);
  EXPECT_NEAR(error.energyRatio, 1.0, 0.05);
}

TEST(Mrcs, SameSeedSameImageAtAnyThreadCountAndRefusesMedia) {
  auto box = test::loadAssetScene("cornell-box");
  Settings s = mrcsSettings(16, 1000, 40, 100);
  const VplSet vpls = generateVpls(*box, s);
  s.threads = 1;
  const MrcsRenderResult one = renderMrcs(*box, vpls, s);
  s.threads = 2;
  const MrcsRenderResult two = renderMrcs(*box, vpls, s);
  for (std::size_t i = 0; i < one.image.pixels.size(); ++i) ASSERT_EQ(one.image.pixels[i], two.image.pixels[i]);
  auto fog = test::loadAssetScene("cornell-fog");
  EXPECT_THROW(renderMrcs(*fog, generateVpls(*fog, s), s), SceneError);
}

}  // namespace
}  // namespace vplab
