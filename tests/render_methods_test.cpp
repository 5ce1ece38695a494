// The render-method table (renderer/offline/render_methods.h): every row renders through its own entry, as the CLI's
// `render --method` and the editor's offline pass call it, a small finite image with light in it. Quick, so that the
// sanitized run goes through every entry (the statistical tests that compare the methods with the reference do too,
// with many more samples, and run in the Release build only: tests/statistical-tests.txt).

#include "renderer/offline/render_methods.h"

#include <gtest/gtest.h>

#include "renderer/image/metrics.h"
#include "renderer/vpl/vpl_generation.h"
#include "tests/test_scenes.h"

namespace vplab {
namespace {

TEST(RenderMethods, EveryRowRendersAFiniteLitImageThroughItsEntry) {
  auto box = test::loadAssetScene("cornell-box");
  auto fog = test::loadAssetScene("cornell-fog");
  for (const RenderMethod& m : renderMethods()) {
    // The media methods on the fog scene; the others where they all apply (lvl refuses media).
    const OfflineScene& scene = m.forMedia ? *fog : *box;
    Settings s = test::smallVplSettings(8, 16);
    s.beamPasses = 2;
    const Settings render = offlineRenderSettings(s, m.id);
    const VplSet vpls = m.usesVpls ? generateVpls(scene, s) : VplSet{};
    const VplRenderResult r = m.render(scene, vpls, render, nullptr, {});
    ASSERT_EQ(r.image.width, 8) << toString(m.id);
    ASSERT_EQ(r.image.height, 8) << toString(m.id);
    EXPECT_EQ(r.nonFiniteSamples, 0u) << toString(m.id);
    for (const glm::vec3& p : r.image.pixels) ASSERT_TRUE(isFinite(p)) << toString(m.id);
    EXPECT_GT(meanLuminance(r.image), 0.0) << toString(m.id);
  }
}

}  // namespace
}  // namespace vplab
