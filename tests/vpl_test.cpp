// Many-light methods on the CPU: VPL generation, rejection, the exact VPL renderer with the clamp bound,
// Kollig-Keller compensation and virtual spherical lights (docs/theory.md §2-§5, §7).

#include "renderer/image/metrics.h"
#include "renderer/offline/embree_scene.h"
#include "renderer/offline/emitter_mask.h"
#include "renderer/offline/light_sampler.h"
#include "renderer/offline/path_tracer.h"
#include "renderer/offline/vpl_renderer.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/vpl/vpl_generation.h"
#include "renderer/vpl/vpl_json.h"
#include "tests/test_scenes.h"
#include "tests/vpl_equal.h"
#include "tests/test_tmp.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <string>

namespace vplab {
namespace {

using Loaded = OfflineScene;

std::unique_ptr<Loaded> load(const std::string& name) { return test::loadAssetScene(name); }

Settings smallSettings(int size, int vpls) { return test::smallVplSettings(size, vpls); }

VplSet generate(const Loaded& l, const Settings& s) { return generateVpls(l, s); }

VplRenderResult render(const Loaded& l, const VplSet& v, Method m, const Settings& s) {
  return renderVpl(l, v, m, s);
}

std::size_t nonFinite(const Image& image) {
  std::size_t n = 0;
  for (const glm::vec3& p : image.pixels) n += isFinite(p) ? 0 : 1;
  return n;
}

/// Mean image luminance of `method` averaged over `seeds` seeds (fresh VPLs per seed).
double meanOverSeeds(const Loaded& l, Settings s, Method method, int seeds) {
  double sum = 0.0;
  for (int i = 0; i < seeds; ++i) {
    s.seed = 1000 + static_cast<uint32_t>(i);
    sum += meanLuminance(render(l, generate(l, s), method, s).image);
  }
  return sum / seeds;
}

// --- generation -------------------------------------------------------------------------------------------

// In the furnace every light path hits a wall; a wall reflects a fraction a of what arrives, so the flux arriving
// at bounce k (what a bounce-k VPL stores; f(x2) reflects it later) sums to Phi_light a^(k-1) in expectation.
TEST(VplGeneration, FurnaceFluxPerBounceIsPowerTimesAlbedoPowers) {
  auto l = load("furnace");
  const float albedo = l->scene().materials[0].baseColor.r;
  const double power = l->lights().totalPower().r;
  Settings s = smallSettings(8, 30000);
  s.vplMaxBounces = 4;
  double sums[5] = {0, 0, 0, 0, 0};
  const int seeds = 2;
  for (int seed = 0; seed < seeds; ++seed) {
    s.seed = 7 + static_cast<uint32_t>(seed);
    VplSet set = generate(*l, s);
    EXPECT_EQ(set.stats.accepted, set.vpls.size());
    EXPECT_EQ(set.stats.candidates, set.vpls.size());
    EXPECT_GT(set.stats.pathsTraced, 0u);
    // vplCount is the expected VPL count: the planned path count lands close to it.
    EXPECT_NEAR(static_cast<double>(set.vpls.size()), s.vplCount, 0.05 * s.vplCount);
    for (const Vpl& v : set.vpls) {
      ASSERT_GE(v.bounce, 1u);
      ASSERT_LE(v.bounce, 4u);
      sums[v.bounce] += v.flux.r;
    }
  }
  for (int k = 1; k <= 4; ++k)
    EXPECT_NEAR(sums[k] / seeds / power, std::pow(albedo, k - 1), 0.04 * std::pow(albedo, k - 1)) << "bounce " << k;
}

// A directional light's paths start uniformly on a disk covering the scene (pdf_A = 1 / (pi R^2)) with weight
// E pi R^2: the flux they bring to a plane is E cos(theta) times its area, whatever R is.
TEST(VplGeneration, DirectionalLightDeliversIrradianceTimesCosineTimesArea) {
  const float half = 2.0f, irradiance = 3.0f;
  const glm::vec3 direction = glm::normalize(glm::vec3(0.0f, -0.8f, 0.6f));
  Loaded l(test::makePlaneUnderDirectionalLight(half, direction, irradiance));
  Settings s = smallSettings(8, 4000);
  s.vplMaxBounces = 1;
  VplSet set = generate(l, s);
  ASSERT_FALSE(set.vpls.empty());
  double sum = 0.0;
  for (const Vpl& v : set.vpls) {
    sum += v.flux.g;
    ASSERT_NEAR(glm::dot(v.incoming, -direction), 1.0f, 1e-5f);  // every VPL saw the sun's own direction
  }
  const double expected = irradiance * 0.8 * (2.0 * half) * (2.0 * half);
  EXPECT_NEAR(sum, expected, 0.02 * expected);
}

TEST(VplGeneration, SameSeedSameVplsAnyThreadCountAndImage) {
  auto l = load("cornell-box");
  Settings s = smallSettings(16, 200);
  s.threads = 1;
  VplSet a = generate(*l, s);
  Image ia = render(*l, a, Method::Vpl, s).image;
  s.threads = 2;
  VplSet b = generate(*l, s);
  Image ib = render(*l, b, Method::Vpl, s).image;
  ASSERT_EQ(a.vpls.size(), b.vpls.size());
  ASSERT_GT(a.vpls.size(), 0u);
  EXPECT_TRUE(test::sameVpls(a.vpls, b.vpls));
  ASSERT_EQ(ia.pixels.size(), ib.pixels.size());
  EXPECT_EQ(0, std::memcmp(ia.pixels.data(), ib.pixels.data(), ia.pixels.size() * sizeof(glm::vec3)));
  s.seed = 2;
  VplSet c = generate(*l, s);
  EXPECT_FALSE(test::sameVpls(a.vpls, c.vpls));
}

/// Fraction of VPLs of `moved` that have a VPL of the same bounce in `original` within `radius`.
double fractionWithin(const VplSet& original, const VplSet& moved, float radius) {
  std::size_t close = 0;
  for (const Vpl& m : moved.vpls) {
    for (const Vpl& o : original.vpls) {
      if (o.bounce == m.bounce && glm::length(o.position - m.position) < radius) {
        ++close;
        break;
      }
    }
  }
  return static_cast<double>(close) / static_cast<double>(std::max<std::size_t>(1, moved.vpls.size()));
}

TEST(VplGeneration, SmallLightMoveMovesVplsCoherently) {
  auto l = load("cornell-box");
  Settings s = smallSettings(16, 400);
  VplSet before = generate(*l, s);
  // Move the light 2 mm along x.
  Scene movedScene = l->scene();
  for (uint32_t tri : movedScene.emissiveTriangles)
    for (int c = 0; c < 3; ++c) movedScene.positions[movedScene.triangles[tri][c]].x += 0.002f;
  movedScene.finalize();
  VplSet after = generate(OfflineScene(std::move(movedScene)), s);
  // A reshuffled set (another seed) as the contrast: the same test must fail for it.
  s.seed = 99;
  VplSet reshuffled = generate(*l, s);
  const float radius = 0.01f;  // 1 cm in a 55 cm box
  double coherent = fractionWithin(before, after, radius);
  double random = fractionWithin(before, reshuffled, radius);
  EXPECT_GT(coherent, 0.8);
  EXPECT_LT(random, 0.5);
}

TEST(VplGeneration, JsonRoundTripIsExact) {
  auto l = load("cornell-box");
  Settings s = smallSettings(16, 50);
  s.rejection = true;
  s.importancePoints = 16;
  s.rejectionPilotVpls = 16;
  VplSet set = generate(*l, s);
  std::string path = vplab::test::tmpPath("vpl_roundtrip.json");
  saveVplSet(path, set);
  VplSet back = loadVplSet(path);
  ASSERT_EQ(back.vpls.size(), set.vpls.size());
  ASSERT_EQ(back.rejected.size(), set.rejected.size());
  EXPECT_TRUE(test::sameVpls(back.vpls, set.vpls));
  EXPECT_EQ(back.stats.pathsTraced, set.stats.pathsTraced);
  EXPECT_EQ(back.stats.candidates, set.stats.candidates);
  EXPECT_THROW(vplSetFromJson("{\"vpls\": [{\"position\": [1, 2]}]}"), VplJsonError);
  EXPECT_THROW(loadVplSet(vplab::test::tmpPath("does-not-exist.json")), VplJsonError);
}

// --- unbiasedness -----------------------------------------------------------------------------------------

TEST(VplUnbiased, FurnaceUnclampedGivesOneOverOneMinusAlbedo) {
  auto l = load("furnace");
  const double albedo = l->scene().materials[0].baseColor.r;
  Settings s = smallSettings(16, 256);
  s.vplMaxBounces = 24;
  s.samplesPerPixel = 2;
  double mean = meanOverSeeds(*l, s, Method::Vpl, 8);
  EXPECT_NEAR(mean, 1.0 / (1.0 - albedo), 0.01 / (1.0 - albedo));
}

/// vpl-kk must converge to the reference; the bound is strong enough to remove a visible share of the energy.
void expectKkMatchesReference(const std::string& name) {
  auto l = load(name);
  Settings s = smallSettings(16, 2048);
  s.components = Components::Indirect;
  s.maxDepth = 32;
  s.vplMaxBounces = 31;
  s.clampBound = 4.0f;
  s.samplesPerPixel = 2;
  Settings ref = s;
  ref.samplesPerPixel = 2048;
  double reference = meanLuminance(renderReference(*l, ref).image);
  // Averaged over seeds: the spread between VPL sets (a few % per seed) is what the tolerance must absorb.
  double kk = meanOverSeeds(*l, s, Method::VplKK, 10);
  double clamped = meanOverSeeds(*l, s, Method::Vpl, 2);
  EXPECT_NEAR(kk / reference, 1.0, 0.01) << name;
  // The clamp alone loses energy that the compensation recovers (otherwise this test would prove nothing).
  EXPECT_LT(clamped / reference, 0.97) << name;
}

TEST(VplUnbiased, KolligKellerMatchesReferenceCornellBox) { expectKkMatchesReference("cornell-box"); }
TEST(VplUnbiased, KolligKellerMatchesReferenceCornellIndirect) { expectKkMatchesReference("cornell-indirect"); }

// --- clamp ------------------------------------------------------------------------------------------------

TEST(VplClamp, EnergyDecreasesMonotonicallyWithTheBound) {
  auto l = load("cornell-box");
  Settings s = smallSettings(24, 256);
  s.components = Components::Indirect;
  VplSet set = generate(*l, s);
  double previousMean = 1e30, previousRemoved = -1.0;
  for (float b : {kInfinity, 100.0f, 20.0f, 5.0f, 1.0f, 0.0f}) {
    s.clampBound = b;
    VplRenderResult r = render(*l, set, Method::Vpl, s);
    double mean = meanLuminance(r.image);
    EXPECT_LE(mean, previousMean) << "b = " << b;
    EXPECT_GE(r.clampEnergyRemoved, previousRemoved) << "b = " << b;
    if (std::isinf(b)) {
      EXPECT_EQ(r.clampEnergyRemoved, 0.0);
    }
    if (b == 0.0f) {
      EXPECT_NEAR(r.clampEnergyRemoved, 1.0, 1e-12);
    }
    previousMean = mean;
    previousRemoved = r.clampEnergyRemoved;
  }
  EXPECT_GT(previousRemoved, 0.99);
}

TEST(VplClamp, InfiniteBoundIsBitIdenticalToUnclamped) {
  auto l = load("cornell-box");
  Settings s = smallSettings(16, 128);
  VplSet set = generate(*l, s);
  s.clampBound = kInfinity;
  Image inf = render(*l, set, Method::Vpl, s).image;
  // Kollig-Keller with no bound has nothing to compensate.
  Image kk = render(*l, set, Method::VplKK, s).image;
  // The largest finite bound is never reached by G in a 55 cm box: the same as no clamp.
  s.clampBound = std::numeric_limits<float>::max();
  Image huge = render(*l, set, Method::Vpl, s).image;
  EXPECT_EQ(0, std::memcmp(inf.pixels.data(), kk.pixels.data(), inf.pixels.size() * sizeof(glm::vec3)));
  EXPECT_EQ(0, std::memcmp(inf.pixels.data(), huge.pixels.data(), inf.pixels.size() * sizeof(glm::vec3)));
}

// --- rejection --------------------------------------------------------------------------------------------

TEST(VplRejection, EpsilonKeepsTheExpectedImage) {
  auto l = load("cornell-box");
  Settings s = smallSettings(16, 128);
  s.components = Components::Indirect;
  s.rejection = true;
  s.rejectionPilotVpls = 64;
  s.importancePoints = 64;
  s.rejectionEpsilon = 1.0f;  // p_i = 1: every candidate accepted, the plain estimator
  double plain = meanOverSeeds(*l, s, Method::Vpl, 12);
  s.rejectionEpsilon = 0.1f;
  double rejected = meanOverSeeds(*l, s, Method::Vpl, 12);
  EXPECT_NEAR(rejected / plain, 1.0, 0.03);
  VplSet set = generate(*l, s);
  EXPECT_LT(set.stats.acceptanceRate, 1.0);
  EXPECT_EQ(set.stats.candidates, set.vpls.size() + set.rejected.size());
}

// Two rooms joined by a door, light in one, camera in the other: about a third of the naive VPLs light nothing
// the camera sees (acceptance ~65% at epsilon = 0.02). At (about) equal accepted VPL count, rejection puts those
// VPLs where they matter: measured relMSE ratio 0.83 (6 seeds, 128 VPLs, 24x24, indirect component).
TEST(VplRejection, TwoRoomsRelMseLowerAtEqualCount) {
  auto l = load("two-rooms");
  Settings s = smallSettings(24, 128);
  s.components = Components::Indirect;
  Settings ref = s;
  ref.samplesPerPixel = 1024;
  Image reference = renderReference(*l, ref).image;
  double plainErr = 0.0, rejectErr = 0.0, plainCount = 0.0, rejectCount = 0.0, acceptance = 0.0;
  const int seeds = 6;
  for (int i = 0; i < seeds; ++i) {
    s.seed = 300 + static_cast<uint32_t>(i);
    s.rejection = false;
    VplSet plain = generate(*l, s);
    plainErr += compareImages(render(*l, plain, Method::Vpl, s).image, reference).relMse;
    plainCount += static_cast<double>(plain.vpls.size());
    s.rejection = true;
    s.rejectionEpsilon = 0.02f;
    VplSet rejected = generate(*l, s);
    rejectErr += compareImages(render(*l, rejected, Method::Vpl, s).image, reference).relMse;
    rejectCount += static_cast<double>(rejected.vpls.size());
    acceptance += rejected.stats.acceptanceRate;
  }
  EXPECT_LT(acceptance / seeds, 0.8);
  EXPECT_NEAR(rejectCount / plainCount, 1.0, 0.1);
  // Asserted factor: rejection lowers relMSE by at least 8% at this count.
  EXPECT_LT(rejectErr, 0.92 * plainErr) << "plain " << plainErr / seeds << " rejection " << rejectErr / seeds;
}

// --- virtual spherical lights -----------------------------------------------------------------------------

TEST(VplVsl, TinyRadiusMatchesPointVpls) {
  auto l = load("cornell-box");
  Settings s = smallSettings(16, 128);
  s.components = Components::Indirect;
  VplSet set = generate(*l, s);
  Image vpl = render(*l, set, Method::Vpl, s).image;
  s.vslRadius = 1e-4f;
  Image vsl = render(*l, set, Method::Vsl, s).image;
  ImageMetrics m = compareImages(vsl, vpl);
  EXPECT_NEAR(m.energyRatioOverall, 1.0, 2e-3);
  EXPECT_LT(m.relMse, 1e-4);
}

// r = 0.05 spreads each VPL over a sphere larger than the box's creases are sharp: the mean over 4 VPL sets must still
// match the unclamped point VPLs', as its sibling below holds r = 0.03 (both without the emitter and its edge).
// Measured 1.0003 (it was one set on 16^2 pixels within 10 %); bounded at 1 %, so a 3 % loss in the VSL transfer fails.
TEST(VplVsl, LargeRadiusIsFiniteAndKeepsEnergy) {
  auto l = load("cornell-box");
  Settings s = smallSettings(32, 128);
  s.components = Components::Indirect;
  s.samplesPerPixel = 2;
  const PixelMask emitters = emitterMask(l->embree(), 32, 32);
  double point = 0.0, vsl = 0.0;
  VplSet set;
  for (uint32_t seed = 1; seed <= 4; ++seed) {
    s.seed = seed;
    s.vslRadius = 0.0f;
    set = generate(*l, s);
    point += meanLuminanceExcluding(render(*l, set, Method::Vpl, s).image, emitters);
    s.vslRadius = 0.05f;
    for (Vpl& v : set.vpls) v.radius = s.vslRadius;
    Image image = render(*l, set, Method::Vsl, s).image;
    EXPECT_EQ(nonFinite(image), 0u);
    vsl += meanLuminanceExcluding(image, emitters);
  }
  std::printf("[ measured ] cornell-box r = 0.05, 4 seeds: VSL / unclamped point VPL indirect mean %.4f\n",
              vsl / point);
  EXPECT_NEAR(vsl / point, 1.0, 0.01);
  // Radius from the VPL density (scaled by vslRadius): finite too.
  s.vslRadius = 1.0f;
  s.vslRadiusFromDensity = true;
  std::vector<float> radii = vslRadii(set.vpls, s, l->scene().bounds.diagonal());
  for (float r : radii) ASSERT_TRUE(r > 0.0f && r < l->scene().bounds.diagonal());
  EXPECT_EQ(nonFinite(render(*l, set, Method::Vsl, s).image), 0u);
}

// A VSL spreads its VPL's light over the surfaces in its sphere instead of removing any (Hasan et al. 2009): on the
// same VPL sets, over seeds, the indirect mean matches unclamped point VPLs; the exact VSL render does not depend on
// the thread count.
TEST(VplVsl, SpreadsEnergyWithoutRemovingItAndIsDeterministic) {
  for (const char* name : {"cornell-box", "cornell-glossy"}) {
    auto l = load(name);
    Settings s = smallSettings(64, 128);
    s.components = Components::Indirect;
    s.samplesPerPixel = 2;
    double point = 0.0, vsl = 0.0;
    for (uint32_t seed = 1; seed <= 4; ++seed) {
      s.seed = seed;
      s.vslRadius = 0.0f;
      VplSet set = generate(*l, s);
      point += meanLuminance(render(*l, set, Method::Vpl, s).image);
      s.vslRadius = 0.03f;
      for (Vpl& v : set.vpls) v.radius = s.vslRadius;
      Image image = render(*l, set, Method::Vsl, s).image;
      vsl += meanLuminance(image);
      if (seed == 1) {
        s.threads = 1;
        Image single = render(*l, set, Method::Vsl, s).image;
        s.threads = 2;
        EXPECT_EQ(0, std::memcmp(image.pixels.data(), single.pixels.data(), image.pixels.size() * sizeof(glm::vec3)))
            << name << ": the VSL render depends on the thread count";
      }
    }
    std::printf("[ measured ] %s r = 0.03, 4 seeds: VSL / unclamped point VPL indirect mean %.4f\n", name,
                vsl / point);
    EXPECT_NEAR(vsl / point, 1.0, 0.02) << name;
  }
}

// --- extremes ---------------------------------------------------------------------------------------------

TEST(VplExtremes, EveryExtremeParameterGivesAFiniteImage) {
  auto l = load("cornell-box");
  struct Case {
    const char* name;
    Method method;
    int vpls;
    float clamp;
    float radius;
    bool reject;
    float epsilon;
  };
  const Case cases[] = {
      {"b=0", Method::Vpl, 32, 0.0f, 0.0f, false, 0.1f},
      {"b=0 kk", Method::VplKK, 32, 0.0f, 0.0f, false, 0.1f},
      {"b=inf", Method::Vpl, 32, kInfinity, 0.0f, false, 0.1f},
      {"r=0", Method::Vsl, 32, kInfinity, 0.0f, false, 0.1f},
      {"huge r", Method::Vsl, 32, kInfinity, 1e6f, false, 0.1f},
      {"eps=0", Method::Vpl, 32, kInfinity, 0.0f, true, 0.0f},
      {"eps=1", Method::Vpl, 32, kInfinity, 0.0f, true, 1.0f},
      {"N=0", Method::VplKK, 0, 1.0f, 0.0f, false, 0.1f},
      {"N=1", Method::Vsl, 1, kInfinity, 0.1f, true, 0.1f},
  };
  for (const Case& c : cases) {
    Settings s = smallSettings(8, c.vpls);
    s.clampBound = c.clamp;
    s.vslRadius = c.radius;
    s.rejection = c.reject;
    s.rejectionEpsilon = c.epsilon;
    s.rejectionPilotVpls = 16;
    s.importancePoints = 16;
    VplSet set = generate(*l, s);
    if (c.vpls == 0) {
      EXPECT_TRUE(set.vpls.empty());
    }
    VplRenderResult result = render(*l, set, c.method, s);
    const Image& image = result.image;
    EXPECT_EQ(result.nonFiniteSamples, 0u) << c.name;  // non-finite samples are left out of the image, so count them
    EXPECT_EQ(nonFinite(image), 0u) << c.name;
    EXPECT_GT(meanLuminance(image), 0.0) << c.name;  // direct light is always there
  }
}

}  // namespace
}  // namespace vplab
