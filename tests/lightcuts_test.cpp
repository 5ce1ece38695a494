// Lightcuts (renderer/offline/lightcuts_renderer.h, light_tree.h, lightcut_bound.h): the light tree holds its VPLs,
// the node bound covers every VPL of the node for Lambert and GGX receivers, a threshold of 0 gives the exact sum of
// renderVpl on the same VPLs, the error bound holds on a closed-form case, and the image does not depend on the
// thread count.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "renderer/core/sampling.h"
#include "renderer/image/metrics.h"
#include "renderer/offline/lightcut_bound.h"
#include "renderer/offline/lightcuts_renderer.h"
#include "renderer/scene/brdf_params.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/vpl/vpl_generation.h"
#include "tests/test_scenes.h"

namespace vplab {
namespace {

glm::vec3 randomUnit(std::mt19937& rng) {
  std::normal_distribution<float> n;
  glm::vec3 v;
  do v = {n(rng), n(rng), n(rng)};
  while (glm::dot(v, v) < 1e-6f);
  return glm::normalize(v);
}

/// VPLs scattered in a box, normals within about 60 degrees of `facing`, incoming directions above their surfaces.
std::vector<Vpl> randomVpls(std::mt19937& rng, int count, const glm::vec3& lo, const glm::vec3& hi,
                            const glm::vec3& facing) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Vpl> vpls(static_cast<std::size_t>(count));
  for (Vpl& v : vpls) {
    v.position = lo + (hi - lo) * glm::vec3(u(rng), u(rng), u(rng));
    v.normal = glm::normalize(facing + 0.6f * randomUnit(rng));
    v.geometricNormal = v.normal;
    glm::vec3 in = randomUnit(rng);
    v.incoming = glm::dot(in, v.normal) > 0.05f ? in : v.normal;
    v.flux = glm::vec3(u(rng), u(rng), u(rng)) * 0.01f + glm::vec3(1e-4f);
  }
  return vpls;
}

/// The VPL indices below `node` (the depth-first layout: its subtree holds the next 2 count - 1 nodes).
std::vector<uint32_t> vplsBelow(const LightTree& tree, uint32_t node) {
  std::vector<uint32_t> out;
  const uint32_t count = tree.nodes()[node].count;
  for (uint32_t i = node; i < node + 2 * count - 1; ++i)
    if (tree.nodes()[i].leaf()) out.push_back(tree.nodes()[i].representative);
  return out;
}

TEST(LightTree, EveryNodeHoldsItsVplsInItsBoxConeAndIntensity) {
  std::mt19937 rng(3);
  const std::vector<Vpl> vpls = randomVpls(rng, 1500, glm::vec3(-1.0f), glm::vec3(1.0f), glm::vec3(0, 1, 0));
  const std::vector<BrdfParams> brdfs(vpls.size(), BrdfParams{glm::vec3(0.5f), 0.0f, 1.0f, 0.0f});
  const LightTree tree(vpls, brdfs, 1, 2);
  ASSERT_EQ(tree.nodes().size(), 2 * vpls.size() - 1);
  EXPECT_EQ(tree.nodes()[0].count, vpls.size());
  std::vector<int> seen(vpls.size(), 0);
  for (uint32_t i = 0; i < tree.nodes().size(); ++i) {
    const LightTreeNode& n = tree.nodes()[i];
    const std::vector<uint32_t> below = vplsBelow(tree, i);
    ASSERT_EQ(below.size(), n.count);
    glm::vec3 sum(0.0f);
    bool repBelow = false;
    for (uint32_t v : below) {
      const glm::vec3& p = vpls[v].position;
      for (int k = 0; k < 3; ++k) ASSERT_TRUE(p[k] >= n.boundsMin[k] && p[k] <= n.boundsMax[k]);
      ASSERT_GE(glm::dot(vpls[v].normal, n.coneAxis), n.coneCos - 1e-5f) << "node " << i;
      sum += tree.intensities()[v];
      repBelow |= v == n.representative;
    }
    EXPECT_TRUE(repBelow);
    EXPECT_NEAR(luminance(sum), luminance(n.intensity), 1e-4f * luminance(sum));
    if (n.leaf()) ++seen[n.representative];
  }
  for (int s : seen) EXPECT_EQ(s, 1);
  // Lambert VPLs: I = Phi albedo / pi exactly.
  EXPECT_FLOAT_EQ(tree.intensities()[7].g, vpls[7].flux.g * 0.5f * kInvPi);
}

TEST(LightTree, VplsSpreadOverManyScalesKeepTheTreeShallow) {
  // Positions 1.3^k, 17 orders of magnitude: the tree stays shallow (the binned splits, and from depth 48 on the
  // median, keep the depth O(log N) and so the build O(N log N)).
  std::vector<Vpl> vpls(150);
  for (std::size_t i = 0; i < vpls.size(); ++i) vpls[i].position = glm::vec3(std::pow(1.3f, static_cast<float>(i)));
  const std::vector<BrdfParams> brdfs(vpls.size(), BrdfParams{glm::vec3(0.5f), 0.0f, 1.0f, 0.0f});
  const LightTree tree(vpls, brdfs, 1, 1);
  std::vector<int> depth(tree.nodes().size(), 0);
  int deepest = 0;
  for (uint32_t i = 0; i < tree.nodes().size(); ++i) {
    const LightTreeNode& n = tree.nodes()[i];
    deepest = std::max(deepest, depth[i]);
    if (n.leaf()) continue;
    depth[i + 1] = depth[n.secondChild] = depth[i] + 1;
  }
  EXPECT_LE(deepest, 48 + 8);
}

TEST(LightTree, RefusesMediumVpls) {
  std::vector<Vpl> vpls(2);
  vpls[1].inMedium = true;
  const std::vector<BrdfParams> brdfs(2);
  EXPECT_THROW(LightTree(vpls, brdfs, 1, 1), std::invalid_argument);
}

/// f(x1) min(G, b) s_i for one VPL: the quantity the node bound must cover (lightcut_bound.h).
float perIntensityContribution(const ShadingPoint& sp, const Vpl& vpl, const BrdfParams& vplBrdf,
                               const glm::vec3& intensity, float b) {
  const glm::vec3 c = vplUnoccludedContribution(sp, vpl, vplBrdf, b);
  float worst = 0.0f;
  for (int k = 0; k < 3; ++k)
    if (intensity[k] > 0.0f) worst = std::max(worst, c[k] / intensity[k]);
  return worst;
}

TEST(LightcutBound, CoversEveryVplOfEveryNodeForLambertAndGgxReceiversAndVpls) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Vpl> vpls = randomVpls(rng, 600, glm::vec3(-1, 0.5f, -1), glm::vec3(1, 2, 1), glm::vec3(0, -1, 0));
  std::vector<BrdfParams> brdfs(vpls.size());
  for (std::size_t i = 0; i < brdfs.size(); ++i)
    brdfs[i] = i % 3 == 0 ? BrdfParams{glm::vec3(u(rng), u(rng), u(rng)), u(rng), 0.05f + 0.9f * u(rng), 1.0f}
                          : BrdfParams{glm::vec3(u(rng), u(rng), u(rng)), 0.0f, 1.0f, 0.0f};
  const LightTree tree(vpls, brdfs, 5, 1);
  int checked = 0, glossyChecked = 0;
  for (int r = 0; r < 60; ++r) {
    ShadingPoint sp;
    sp.hit.position = glm::vec3(2.0f * u(rng) - 1.0f, 1.2f * u(rng) - 0.2f, 2.0f * u(rng) - 1.0f);
    sp.hit.shadingNormal = sp.hit.geometricNormal = glm::normalize(glm::vec3(0, 1, 0) + 0.8f * randomUnit(rng));
    glm::vec3 wo = randomUnit(rng);
    if (glm::dot(wo, sp.hit.shadingNormal) < 0.0f) wo = -wo;
    sp.wo = wo;
    const bool glossy = r % 2 == 1;
    sp.brdf = glossy ? BrdfParams{glm::vec3(0.9f, 0.5f, 0.2f), r % 4 == 1 ? 1.0f : 0.0f, 0.02f + 0.5f * u(rng), 1.0f}
                     : BrdfParams{glm::vec3(0.7f), 0.0f, 1.0f, 0.0f};
    for (float b : {kInfinity, 10.0f}) {
      for (uint32_t i = 0; i < tree.nodes().size(); i += 7) {
        const LightTreeNode& node = tree.nodes()[i];
        const float bound = lightcutBound(sp, node, b);
        for (uint32_t v : vplsBelow(tree, i)) {
          const float c = perIntensityContribution(sp, vpls[v], brdfs[v], tree.intensities()[v], b);
          ASSERT_LE(c, bound * (1.0f + 1e-4f) + 1e-12f)
              << "node " << i << " VPL " << v << " receiver " << r << " b " << b;
          if (c > 0.0f) ++checked, glossyChecked += glossy ? 1 : 0;
        }
      }
    }
  }
  EXPECT_GT(checked, 10000);
  EXPECT_GT(glossyChecked, 3000);
}

TEST(Lightcuts, ErrorBoundHoldsOnAClosedFormCase) {
  // A white plane y = 0 under VPLs spread over a square at y = 1 facing down, nothing between them: every VPL is
  // visible and the exact sum is sum_i (rho / pi)(albedo / pi) Phi_i min(h^2 / d_i^4, b) (Lambert at both ends).
  OfflineScene offline(test::makePlaneUnderPointLight(3.0f, glm::vec3(0, 5, 0), 1.0f));
  std::mt19937 rng(7);
  std::vector<Vpl> vpls = randomVpls(rng, 3000, glm::vec3(-1, 1, -1), glm::vec3(1, 1, 1), glm::vec3(0, -1, 0));
  for (Vpl& v : vpls) v.normal = v.geometricNormal = v.incoming = glm::vec3(0, -1, 0);
  const float albedo = 0.6f, rho = 0.8f;
  const std::vector<BrdfParams> brdfs(vpls.size(), BrdfParams{glm::vec3(albedo), 0.0f, 1.0f, 0.0f});
  const LightTree tree(vpls, brdfs, 1, 2);
  for (float b : {kInfinity, 4.0f}) {
    for (float threshold : {0.002f, 0.02f, 0.2f}) {
      const LightcutGather gather(offline.embree(), vpls, brdfs, tree, b, threshold, 1 << 20);
      double worstRatio = 0.0;
      for (int p = 0; p < 40; ++p) {
        ShadingPoint sp;
        sp.hit.position = glm::vec3(-1.5f + 3.0f * (p % 8) / 7.0f, 0.0f, -1.5f + 3.0f * (p / 8) / 4.0f);
        sp.hit.shadingNormal = sp.hit.geometricNormal = glm::vec3(0, 1, 0);
        sp.wo = glm::normalize(glm::vec3(0.3f, 1.0f, 0.1f));
        sp.brdf = BrdfParams{glm::vec3(rho), 0.0f, 1.0f, 0.0f};
        double exact = 0.0;
        for (const Vpl& v : vpls) {
          const glm::dvec3 d = glm::dvec3(v.position) - glm::dvec3(sp.hit.position);
          const double d2 = glm::dot(d, d);
          const double g = d.y * d.y / (d2 * d2);
          exact += (rho / kPi) * (albedo / kPi) * static_cast<double>(v.flux.g) * std::min(g, static_cast<double>(b));
        }
        const Lightcut cut = gather.gather(sp);
        const double error = std::abs(static_cast<double>(cut.radiance.g) - exact);
        // The bound is on luminance; a grey receiver and grey VPLs make every channel's error equal to it.
        EXPECT_LE(error, cut.errorBound * 1.001 + 1e-6 * exact) << "point " << p << " threshold " << threshold;
        EXPECT_FALSE(cut.maxReached);
        // Each node's bound is under the threshold of the estimate; the relative error stays near it too.
        worstRatio = std::max(worstRatio, error / exact);
        if (threshold == 0.002f) {
          EXPECT_LT(cut.nodes, vpls.size() / 2) << "the cut should be sublinear";
        }
      }
      EXPECT_LT(worstRatio, 10.0 * threshold) << "threshold " << threshold << " b " << b;
    }
  }
}

Settings lightcutsSettings() {
  Settings s = test::smallVplSettings(32, 3000);
  s.clampBound = 10.0f;
  s.components = Components::Indirect;
  return s;
}

TEST(Lightcuts, ThresholdZeroGivesTheExactSumOfTheSameVpls) {
  auto box = test::loadAssetScene("cornell-box");
  for (float b : {10.0f, kInfinity}) {
    Settings s = lightcutsSettings();
    s.clampBound = b;
    s.lightcutError = 0.0f;
    s.lightcutMax = 1 << 24;
    const VplSet vpls = generateVpls(*box, s);
    ASSERT_GT(vpls.vpls.size(), 2000u);
    const VplRenderResult exact = renderVpl(*box, vpls, Method::Vpl, s);
    const LightcutsRenderResult cut = renderLightcuts(*box, vpls, Method::Lightcuts, s);
    EXPECT_EQ(cut.cutsAtMax, 0u);
    double worst = 0.0;
    for (std::size_t i = 0; i < exact.image.pixels.size(); ++i) {
      const float e = luminance(exact.image.pixels[i]), c = luminance(cut.image.pixels[i]);
      worst = std::max(worst, std::abs(static_cast<double>(c) - e) / std::max(1e-6, static_cast<double>(e)));
    }
    // Float summation in another order only.
    EXPECT_LT(worst, 1e-4) << "b " << b;
    EXPECT_NEAR(cut.clampEnergyRemoved, exact.clampEnergyRemoved, 1e-4);
  }
}

TEST(Lightcuts, OnePercentStaysNearTheExactSumWithSmallCuts) {
  auto box = test::loadAssetScene("cornell-box");
  Settings s = lightcutsSettings();
  const VplSet vpls = generateVpls(*box, s);
  const VplRenderResult exact = renderVpl(*box, vpls, Method::Vpl, s);
  const LightcutsRenderResult cut = renderLightcuts(*box, vpls, Method::Lightcuts, s);
  const PixelRelativeError error = pixelRelativeError(cut.image, exact.image);
  ASSERT_GT(error.pixels, 500u);
  EXPECT_LT(error.mean, 0.03);
  EXPECT_NEAR(error.energyRatio, 1.0, 0.02);
  EXPECT_LT(cut.meanCut, 0.5 * static_cast<double>(vpls.vpls.size()));
  EXPECT_LT(cut.shadowRays, exact.shadowRays / 2);
}

TEST(Lightcuts, SameSeedSameImageAtAnyThreadCount) {
  auto box = test::loadAssetScene("cornell-box");
  Settings s = lightcutsSettings();
  s.components = Components::All;
  const VplSet vpls = generateVpls(*box, s);
  s.threads = 1;
  const LightcutsRenderResult one = renderLightcuts(*box, vpls, Method::LightcutsKK, s);
  s.threads = 2;
  const LightcutsRenderResult two = renderLightcuts(*box, vpls, Method::LightcutsKK, s);
  ASSERT_EQ(one.image.pixels.size(), two.image.pixels.size());
  for (std::size_t i = 0; i < one.image.pixels.size(); ++i) ASSERT_EQ(one.image.pixels[i], two.image.pixels[i]);
  EXPECT_EQ(one.shadowRays, two.shadowRays);
}

TEST(Lightcuts, RefusesMediaAndVsls) {
  auto fog = test::loadAssetScene("cornell-fog");
  Settings s = test::smallVplSettings(4, 16);
  const VplSet fogVpls = generateVpls(*fog, s);
  EXPECT_THROW(renderLightcuts(*fog, fogVpls, Method::Lightcuts, s), SceneError);
  auto box = test::loadAssetScene("cornell-box");
  s.vslRadius = 0.05f;
  const VplSet vpls = generateVpls(*box, s);
  EXPECT_THROW(renderLightcuts(*box, vpls, Method::Lightcuts, s), std::invalid_argument);
}

}  // namespace
}  // namespace vplab
