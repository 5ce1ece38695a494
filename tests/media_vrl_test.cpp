// Virtual ray lights (Novak et al. 2012a, docs/theory.md §19) and progressive virtual beam lights (Novak et al.
// 2012b, §20): against the path-traced reference on the fog Cornell box, the fog furnace's closed form, degenerate
// media, and the paper's claim of lower error than unbounded medium VPLs at equal time.

#include "renderer/image/metrics.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/offline/path_tracer.h"
#include "renderer/offline/vpl_renderer.h"
#include "renderer/offline/vrl_renderer.h"
#include "renderer/vpl/vpl_generation.h"
#include "tests/media_test_util.h"
#include "tests/test_scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

namespace vplab {
namespace {

using test::boxMedium;
using test::spaceMedium;

bool allFinite(const Image& image) {
  for (const glm::vec3& p : image.pixels)
    if (!isFinite(p)) return false;
  return true;
}

// The INDIRECT part of the bundled cornell-fog scene at 12^2, path traced with 1024 spp, shared by the tests below.
// VRLs and beams change only the indirect part (the direct part, emission, direct light and single scattering, is
// the VPL render's own estimator, tested against the reference in media_vpl_test.cpp); at 12^2 the directly seen
// light's pixels and their jitter make the full image's mean spread by 13 % per render at 4 spp (measured), far
// beyond what the VRLs are tested for.
Settings fogSettings(int vpls) {
  Settings s = test::smallVplSettings(12, vpls);
  s.components = Components::Indirect;
  s.vrlSamples = 1;
  return s;
}

const Image& fogIndirectReference(const OfflineScene& scene) {
  static const Image reference = [&] {
    Settings r = fogSettings(0);
    r.samplesPerPixel = 1024;
    return renderReference(scene, r).image;
  }();
  return reference;
}

TEST(MediaVrl, FogCornellAgreesWithTheReference) {
  auto scene = test::loadAssetScene("cornell-fog");
  const double ref = meanLuminance(fogIndirectReference(*scene));
  ASSERT_GT(ref, 0.0);
  // One render (12^2, 1 spp, 4096 VPLs) spreads by 2.5 % (relative standard deviation over 32 seeds, measured):
  // eight average to about 0.9 %.
  const int seeds = 8;
  double vrl = 0.0;
  for (int i = 0; i < seeds; ++i) {
    Settings v = fogSettings(4096);
    v.seed = 70 + 13 * static_cast<uint32_t>(i);
    const VplSet set = generateVpls(*scene, v);
    ASSERT_FALSE(set.vrls.empty());
    VplRenderResult r = renderVrl(*scene, set, v);
    EXPECT_EQ(r.nonFiniteSamples, 0u);
    EXPECT_EQ(r.clampEnergyRemoved, 0.0);
    vrl += meanLuminance(r.image) / seeds;
  }
  Settings b = fogSettings(2048);
  b.seed = 900;
  b.beamPasses = 16;
  int passesSeen = 0;
  VplRenderResult vbl = renderVbl(*scene, b, nullptr, [&](const Image&, int) { ++passesSeen; });
  EXPECT_EQ(passesSeen, 16);
  EXPECT_EQ(vbl.samplesPerPixel, 16);
  EXPECT_EQ(vbl.nonFiniteSamples, 0u);
  const double beams = meanLuminance(vbl.image);
  std::printf("[ measured ] cornell-fog 12^2 indirect: reference %.5f; vrl (8 x 4096 VPLs) %.4f, vbl (16 passes x "
              "2048 VPLs) %.4f of the reference\n",
              ref, vrl / ref, beams / ref);
  EXPECT_NEAR(vrl / ref, 1.0, 0.03);
  EXPECT_NEAR(beams / ref, 1.0, 0.03);
}

// A closed furnace (walls emit 1, albedo 0.5) in a non-absorbing medium keeps L = 2 everywhere (docs/theory.md §16).
// What the medium adds is checked apart from the walls: a pixel gets 2 T from the walls (T its camera ray's
// transmittance) and 2 (1 - T) in-scattered, 1.09 of the image's 2 here (test::furnaceMediumPart); the error of
// the image mean is taken relative to that part. Single sets spread by the surface VPLs' unbounded 1/d^2: per set
// 5.0 % of the medium's part for 2048 VPLs at 12^2, 1.9 % for 8192 VPLs at 6^2 at the same cost (standard deviations
// over 8 sets), so eight of the latter have a standard error of 0.7 %; the beams' 24 passes spread by 0.45 %.
// Measured: vrl -0.6 %, vbl -0.4 % (were -1.5 % and -0.4 % with 2048 VPLs at 12^2). Bound 2.5 % of the medium's part
// for both (3.7 standard errors for vrl), below the 5 % of an error in the in-scattering, which fails them (checked:
// the medium's part of every camera sample times 1.05 or 0.95).
TEST(MediaVrl, FurnaceWithFogStaysAtTwo) {
  Scene scene = test::makeFurnaceBox(0.5f);
  scene.media.push_back(spaceMedium(glm::vec3(0.0f), glm::vec3(0.4f, 0.7f, 1.0f), 0.5f));
  OfflineScene offline(std::move(scene));
  Settings s = test::smallVplSettings(6, 8192);
  s.vrlSamples = 1;
  double vrl = 0.0;
  const int seeds = 8;
  for (int i = 0; i < seeds; ++i) {
    Settings v = s;
    v.seed = 20 + 17 * static_cast<uint32_t>(i);
    VplRenderResult r = renderVrl(offline, generateVpls(offline, v), v);
    ASSERT_TRUE(allFinite(r.image));
    vrl += meanLuminance(r.image) / seeds;
  }
  Settings b = test::smallVplSettings(12, 1024);
  b.vrlSamples = 1;
  b.beamPasses = 24;
  const double vbl = meanLuminance(renderVbl(offline, b).image);
  const double vrlMedium = luminance(glm::vec3(test::furnaceMediumPart(offline, s.width, s.height)));
  const double vblMedium = luminance(glm::vec3(test::furnaceMediumPart(offline, b.width, b.height)));
  const double vrlError = (vrl - 2.0) / vrlMedium, vblError = (vbl - 2.0) / vblMedium;
  std::printf("[ measured ] fog furnace (sigma_s = 0.4/0.7/1, g = 0.5): vrl (6^2, 8 x 8192 VPLs) %.4f, vbl (12^2, 24 "
              "passes x 1024 VPLs) %.4f (exact 2; the medium's part %.4f: vrl %+.2f %%, vbl %+.2f %% of it)\n",
              vrl, vbl, vrlMedium, 100.0 * vrlError, 100.0 * vblError);
  EXPECT_NEAR(vrlError, 0.0, 0.025);
  EXPECT_NEAR(vblError, 0.0, 0.025);
}

TEST(MediaVrl, OpticallyHugeMediumIsFinite) {
  auto base = test::loadAssetScene("cornell-box");
  Scene scene = base->scene();
  scene.media.push_back(boxMedium(scene.geometryBounds.center(), 0.3f * scene.geometryBounds.extent(),
                                  glm::vec3(1e6f), glm::vec3(1e6f), 0.9f));
  OfflineScene offline(std::move(scene));
  Settings s = test::smallVplSettings(16, 64);
  s.beamPasses = 2;
  VplRenderResult vrl = renderVrl(offline, generateVpls(offline, s), s);
  EXPECT_TRUE(allFinite(vrl.image));
  EXPECT_EQ(vrl.nonFiniteSamples, 0u);
  VplRenderResult vbl = renderVbl(offline, s);
  EXPECT_TRUE(allFinite(vbl.image));
  EXPECT_EQ(vbl.nonFiniteSamples, 0u);
}

// Without media there are no VRLs and every VPL is on a surface: the VRL render is the unbounded VPL render, bit for
// bit (the same random numbers, the same sums).
TEST(MediaVrl, WithoutMediaEqualsTheVplRender) {
  auto scene = test::loadAssetScene("cornell-box");
  Settings s = test::smallVplSettings(16, 64);
  s.samplesPerPixel = 2;
  const VplSet set = generateVpls(*scene, s);
  ASSERT_TRUE(set.vrls.empty());
  const Image a = renderVpl(*scene, set, Method::Vpl, s).image;
  const Image b = renderVrl(*scene, set, s).image;
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  for (std::size_t i = 0; i < a.pixels.size(); ++i) ASSERT_EQ(a.pixels[i], b.pixels[i]) << i;
}

TEST(MediaVrl, BeamRadiusShrinksBySchedule) {
  Settings s;
  s.beamRadius = 0.1f;
  s.beamShrink = 0.5f;
  EXPECT_FLOAT_EQ(beamRadiusForPass(s, 10.0f, 0), 0.1f);
  EXPECT_NEAR(beamRadiusForPass(s, 10.0f, 3), 0.1f * std::pow(4.0f, -0.25f), 1e-6f);
  s.beamRadius = 0.0f;
  EXPECT_FLOAT_EQ(beamRadiusForPass(s, 10.0f, 0), 0.2f);  // 2 % of the diagonal
  s.beamShrink = 1.0f;
  EXPECT_FLOAT_EQ(beamRadiusForPass(s, 10.0f, 7), 0.2f);
}

// Novak et al. 2012a: VRLs beat medium VPLs (whose 1/d^2 in the medium splotches). Two comparisons over eight seeds
// (single renders are heavy tailed: one seed measured vpl 0.109 against vrl 0.023 on fog-shaft, another a tie):
// - the same light paths (equal VPL sets): the VRLs' relMSE is lower;
// - equal time: unbounded `vpl` gets twice the VPLs until its eight renders take at least the VRL renders' time.
//   Here the claim does not hold reliably at 12^2, so it is printed, not asserted: the VRL render costs about 2.3x
//   the VPL render of the same set, and the surface VPLs' unbounded 1/d^2 (which VRLs leave as they are) dominates
//   the error and shrinks with the extra VPLs. Five seed bases (this one first) measured vrl/vpl relMSE 0.017/0.012, 0.050/0.014,
//   0.020/0.023, 0.018/0.022, 0.035/0.212 at equal time, and 0.017/0.028, 0.050/0.072, 0.020/0.027, 0.018/0.025,
//   0.035/0.058 on the same sets.
// The same light paths as VRLs and as unbounded medium VPLs: spreading each segment's light along it removes the
// medium VPLs' specks. (Equal-time comparisons are the bench's: docs/methods.md "The course's media comparison".)
TEST(MediaVrl, LowerErrorThanUnboundedVplsFromTheSameLightPaths) {
  auto scene = test::loadAssetScene("cornell-fog");
  const Image& reference = fogIndirectReference(*scene);
  const int seeds = 8;
  double vrlErr = 0.0, vplErr = 0.0;
  for (int i = 0; i < seeds; ++i) {
    Settings s = fogSettings(256);
    s.samplesPerPixel = 2;
    s.seed = 5 + 31 * static_cast<uint32_t>(i);
    const VplSet set = generateVpls(*scene, s);
    vrlErr += compareImages(renderVrl(*scene, set, s).image, reference).relMse / seeds;
    vplErr += compareImages(renderVpl(*scene, set, Method::Vpl, s).image, reference).relMse / seeds;
  }
  std::printf("[ measured ] cornell-fog 12^2 indirect vs reference, mean relMSE of %d seeds of 256 VPLs: vrl %.5f, "
              "unbounded vpl %.5f\n",
              seeds, vrlErr, vplErr);
  EXPECT_LT(vrlErr, vplErr);
}

}  // namespace
}  // namespace vplab
