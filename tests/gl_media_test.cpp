// Participating media in the GL preview (renderer/gl/media_pass.h, docs/theory.md §16-§18) against the CPU's exact VPL
// render on the same VPLs (renderer/offline/vpl_renderer.h: transmittance on every transfer, each VPL's in-scattering
// at an equiangular distance of its own, the bound b) and against the CPU's single scattering of the lights, on the
// bundled fog scenes. The preview point-samples pixel centres with one distance per VPL and pixel, the CPU jitters
// its pixel samples: the preview is rendered at 4x the resolution and box-filtered down before comparing. Every test
// runs on OSMesa and on EGL.

#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "renderer/gl/preview_renderer.h"
#include "renderer/image/metrics.h"
#include "renderer/offline/camera_sample.h"
#include "renderer/offline/emitter_mask.h"
#include "renderer/offline/vpl_renderer.h"
#include "renderer/vpl/vpl_generation.h"
#include "tests/cpu_image_cache.h"
#include "tests/gl_test_util.h"
#include "tests/media_test_util.h"
#include "tests/test_scenes.h"

namespace vplab {
namespace {

class GlMedia : public test::GlBackendTest {};

constexpr int kUpscale = 4;

/// The preview at kUpscale x the settings' size, box-filtered down.
Image previewDownscaled(const Scene& scene, const VplSet& vpls, Settings s, PreviewOutput which) {
  s.width *= kUpscale;
  s.height *= kUpscale;
  PreviewRenderer renderer;
  renderer.render(scene, vpls, s, scene.camera);
  return blockAverage(renderer.readLinear(which), kUpscale);
}

struct Comparison {
  double relMse, meanRatio;
};

Comparison compare(const OfflineScene& l, const Image& gl, const Image& cpu, const char* what, int edge = 1) {
  const PixelMask emitters = emitterMask(l.embree(), cpu.width, cpu.height, edge);
  // Both scaled by the CPU image's mean, so that relMSE weighs a dim image's errors as a bright one's.
  const double scale = unitMeanScale(cpu, emitters);
  const ImageMetrics m = compareImagesExcluding(scaled(gl, scale), scaled(cpu, scale), emitters);
  const double ratio = meanRatioExcludingEmitters(gl, cpu, emitters);
  std::printf("[ measured ] %s: relMSE %.5f, mean ratio %.4f (%zu emitter pixels left out)\n", what, m.relMse, ratio,
              emitters.count());
  EXPECT_EQ(m.nonFinitePixels, 0u) << what;
  return {m.relMse, ratio};
}

/// The preview's indirect light (the VPLs: the gather attenuated along the camera rays, plus the VPLs' in-scattering)
/// against the CPU's exact VPL render of the indirect component, on the same VPLs, surface and medium ones.
void expectIndirectMatchesCpu(const std::string& name, float bound, int size, int vplCount, int k = 1, int grid = 1) {
  auto l = test::loadAssetScene(name);
  Settings s = test::indirectSettings(size, vplCount);
  s.clampBound = bound;
  s.interleave = k;
  s.indirectDownscale = grid;
  VplSet vpls = generateVpls(*l, s);
  std::size_t inMedium = 0;
  for (const Vpl& v : vpls.vpls) inMedium += v.inMedium;
  ASSERT_GT(inMedium, 0u) << name << ": no medium VPLs to test";
  const Image gl = previewDownscaled(l->scene(), vpls, s, PreviewOutput::Indirect);
  Settings c = s;
  c.samplesPerPixel = 64;
  const Image& cpu = test::cachedVplRender(*l, vpls, Method::Vpl, c);
  const std::string what = name + " indirect, " + std::to_string(vpls.vpls.size()) + " VPLs (" +
                           std::to_string(inMedium) + " in the medium), b = " + std::to_string(bound);
  const Comparison m = compare(*l, gl, cpu, what.c_str());
  EXPECT_LE(m.relMse, 0.02);
  EXPECT_NEAR(m.meanRatio, 1.0, 0.02);
  // The VPLs' in-scattering along the camera rays is a good part of it, so a comparison without it would fail.
  const double scattered = meanLuminance(previewDownscaled(l->scene(), vpls, s, PreviewOutput::Scattered)) -
                           meanLuminance(previewDownscaled(l->scene(), VplSet{}, s, PreviewOutput::Scattered));
  std::printf("[ measured ] %s: the VPLs' in-scattering is %.1f %% of the indirect mean\n", name.c_str(),
              100.0 * scattered / meanLuminance(gl));
  EXPECT_GT(scattered, 0.1 * meanLuminance(gl));
}

TEST_P(GlMedia, FogCornellIndirectMatchesCpu) {
  expectIndirectMatchesCpu("cornell-fog", 20.0f, 64, 64);
}

TEST_P(GlMedia, FogShaftIndirectMatchesCpu) {
  expectIndirectMatchesCpu("fog-shaft", 20.0f, 64, 64);
}
// The benchmark's configuration: interleaved over 4 x 4 subsets and on the half-resolution grid, with more VPLs.
TEST_P(GlMedia, FogCornellInterleavedOnTheGridMatchesCpu) {
  expectIndirectMatchesCpu("cornell-fog", 20.0f, 64, 256, 4, 2);
}

/// The lights' single scattering (the preview's Scattered output without VPLs) against the CPU's.
void expectSingleScatteringMatchesCpu(const std::string& name, int size) {
  auto l = test::loadAssetScene(name);
  Settings s = test::indirectSettings(size, 0);
  const Image gl = previewDownscaled(l->scene(), VplSet{}, s, PreviewOutput::Scattered);
  const Image& cpu = test::cachedCpu("cpuSingleScattering 256", test::renderInputs(l->scene(), s),
                                     [&] { return test::cpuSingleScattering(*l, s, 256); });
  const Comparison m = compare(*l, gl, cpu, (name + " single scattering").c_str());
  EXPECT_LE(m.relMse, 0.02);
  EXPECT_NEAR(m.meanRatio, 1.0, 0.02);
}

TEST_P(GlMedia, FogShaftSingleScatteringMatchesCpu) {
  expectSingleScatteringMatchesCpu("fog-shaft", 64);
}

TEST_P(GlMedia, FogCornellSingleScatteringMatchesCpu) {
  expectSingleScatteringMatchesCpu("cornell-fog", 64);
}

// Approximate bias compensation in the medium (media_pass.h, Engelhardt et al. 2012): what the preview's compensation
// adds to the scattered light (its Scattered output with compensation on minus the one without: C times the bounded
// in-scattering) against what the CPU's vpl-abc adds in the medium on the same VPLs and bound
// (test::cpuMediumCompensation: its compensation at a forced flight along each camera ray, nothing else). Both take
// the medium homogeneous and unbounded over the ball of radius 1/sqrt(b) and stop after one residual bounce; the CPU
// evaluates the bounded light at the ball's points (with their visibility, some of them beyond the walls), the preview
// takes it equal to the camera ray's, and returns more. Measured (both backends alike): preview / CPU 1.235, 1.237,
// 1.250, 1.236, 1.267 over five CPU estimates of 256 samples per pixel (mean 1.245, standard deviation 0.013, 1.1 %),
// 1.248 at 1024; the preview's own model evaluated on the CPU at the camera ray's points (C times the direct light and
// the bounded gather there) gives 0.99-1.02. Bound: 1.245 within 3.5 % (three standard deviations), below the 5 % of
// an error in the compensation, which fails it (checked: the factor C times 1.05 or 0.95).
// Then the whole image with compensation (SSBC on the surfaces, the media's) against the CPU's vpl-kk (exact
// compensation, Kollig & Keller on surfaces, Raab et al. in media): closer than without.
TEST_P(GlMedia, CompensationReturnsTheEnergyTheBoundRemoves) {
  auto l = test::loadAssetScene("cornell-fog");
  Settings s = test::indirectSettings(32, 256);
  s.components = Components::All;
  const float bound = 20.0f;
  s.clampBound = bound;
  VplSet vpls = generateVpls(*l, s);
  auto scattered = [&](float b, int ssbcSteps) {
    Settings t = s;
    t.clampBound = b;
    t.ssbcSteps = ssbcSteps;
    return previewDownscaled(l->scene(), vpls, t, PreviewOutput::Scattered);
  };
  const Image bounded = scattered(bound, 0);
  Image gl = scattered(bound, 2);
  for (std::size_t i = 0; i < gl.pixels.size(); ++i) gl.pixels[i] -= bounded.pixels[i];
  const double unbounded = meanLuminance(scattered(kInfinity, 0));
  const double removed = unbounded - meanLuminance(bounded), returned = meanLuminance(gl);
  EXPECT_GT(removed, 0.02 * unbounded);
  const Image& cpu = test::cachedCpu("cpuMediumCompensation vpl-abc 256", test::renderInputs(l->scene(), s, &vpls),
                                     [&] { return test::cpuMediumCompensation(*l, vpls, Method::VplAbc, s, 256); });
  const double ratio = returned / meanLuminance(cpu);
  const ImageMetrics blocks =
      compareAtUnitMean(blockAverage(gl, 4), blockAverage(cpu, 4), PixelMask(s.width / 4, s.height / 4));
  std::printf(
      "[ measured ] cornell-fog medium, b = %g: the bound removes %.1f %% of the scattered light, the compensation "
      "returns %.0f %% of that; the compensation / CPU vpl-abc's in the medium %.4f (4x4-block relMSE at unit mean "
      "%.4f)\n",
      bound, 100.0 * removed / unbounded, 100.0 * returned / removed, ratio, blocks.relMse);
  EXPECT_EQ(blocks.nonFinitePixels, 0u);
  EXPECT_NEAR(ratio / 1.245, 1.0, 0.035);

  Settings t = s;
  const Image withoutCompensation = previewDownscaled(l->scene(), vpls, t, PreviewOutput::Final);
  t.ssbcSteps = 2;
  const Image withCompensation = previewDownscaled(l->scene(), vpls, t, PreviewOutput::Final);
  Settings c = t;
  c.samplesPerPixel = 64;
  const PixelMask emitters = emitterMask(l->embree(), s.width, s.height, 1);
  const Image& kk = test::cachedVplRender(*l, vpls, Method::VplKK, c);
  const double before = meanRatioExcludingEmitters(withoutCompensation, kk, emitters);
  const double after = meanRatioExcludingEmitters(withCompensation, kk, emitters);
  std::printf("[ measured ] cornell-fog b = %g, whole image / CPU vpl-kk: %.4f without compensation, %.4f with (SSBC "
              "and the media's)\n",
              bound, before, after);
  EXPECT_GT(after, before + 0.05);
}

// Same scene, settings and seed: the same image, bit for bit (the media passes draw no random numbers of their own
// but per-pixel hashes).
TEST_P(GlMedia, SameSettingsGiveTheSameImage) {
  auto l = test::loadAssetScene("fog-shaft");
  Settings s = test::indirectSettings(64, 64);
  s.clampBound = 20.0f;
  s.interleave = 2;
  VplSet vpls = generateVpls(*l, s);
  PreviewRenderer a, b;
  a.render(l->scene(), vpls, s, l->scene().camera);
  b.render(l->scene(), vpls, s, l->scene().camera);
  EXPECT_EQ(test::differingPixels(a.readLinear(), b.readLinear()), 0u);
}

// The invalidation model (renderer/invalidation.h) with media: the bound changes the gather and the VPLs' in-scattering
// but neither the VPLs' maps nor the direct light; a camera move redoes the media passes; a medium edited in place is
// noticed (its coefficients change the direct light's transmittance and the scattering), and the image changes.
TEST_P(GlMedia, PassesFollowTheInvalidationModel) {
  auto l = test::loadAssetScene("cornell-fog");
  Scene scene = l->scene();
  Settings s = test::indirectSettings(32, 32);
  s.clampBound = 20.0f;
  VplSet vpls = generateVpls(*l, s);
  PreviewRenderer renderer;
  renderer.render(scene, vpls, s, scene.camera);
  const PreviewCounters first = renderer.counters();
  EXPECT_EQ(first.media, 1);
  renderer.render(scene, vpls, s, scene.camera);
  EXPECT_EQ(renderer.counters().media, 1) << "nothing changed";

  s.clampBound = 5.0f;
  renderer.render(scene, vpls, s, scene.camera);
  PreviewCounters c = renderer.counters();
  EXPECT_EQ(c.media, 2);
  EXPECT_EQ(c.gather, first.gather + 1);
  EXPECT_EQ(c.direct, first.direct);
  EXPECT_EQ(c.vplShadowMaps, first.vplShadowMaps);

  Camera moved = scene.camera;
  moved.position.x += 0.01f;
  renderer.render(scene, vpls, s, moved);
  EXPECT_EQ(renderer.counters().media, 3);

  const Image before = renderer.readLinear();
  scene.media[0].sigmaS *= 0.5f;
  renderer.render(scene, vpls, s, moved);
  c = renderer.counters();
  EXPECT_EQ(c.media, 4);
  EXPECT_EQ(c.direct, first.direct + 2);  // the camera move, then the medium
  EXPECT_GT(test::differingPixels(renderer.readLinear(), before), 0u);
}

// The editor's budgeted render through fog (PreviewRenderer::render): with a zero budget every call stops after one
// slice, a draw or a band of rows of one, so the G-buffer, the direct light, the media and the compensation each span
// several calls; a medium edit while the direct light is half drawn and a new bound while the media are half drawn
// restart what they change. The image at the end is the one an unbudgeted call gives, bit for bit. The benchmark's layout (k = 4 on the
// half-resolution grid), at a size whose blocks are not a multiple of the first bands' rows.
TEST_P(GlMedia, BudgetedRenderGivesTheUnbudgetedImage) {
  auto l = test::loadAssetScene("cornell-fog");
  Scene scene = l->scene();
  Settings s = test::indirectSettings(40, 64);
  s.height = 36;
  s.components = Components::All;
  s.clampBound = 20.0f;
  s.ssbcSteps = 2;
  s.interleave = 4;
  s.indirectDownscale = 2;
  VplSet vpls = generateVpls(*l, s);
  PreviewRenderer stepped;
  int calls = 0, gbufferCalls = 0, directCalls = 0, mediaCalls = 0, ssbcCalls = 0;
  bool mediumEdited = false, boundChanged = false;
  PreviewTimings t;
  do {
    t = stepped.render(scene, vpls, s, scene.camera, 0.0);
    const bool direct = t.directWallMs > 0.0, media = t.mediaWallMs > 0.0;
    gbufferCalls += t.gbufferWallMs > 0.0;
    directCalls += direct;
    mediaCalls += media;
    ssbcCalls += t.ssbcWallMs > 0.0;
    if (direct && directCalls == 3 && !t.complete) {
      scene.media[0].sigmaS *= 0.8f;  // an edit in place, as the editor's media panel makes
      mediumEdited = true;
    }
    if (media && mediaCalls == 3 && !t.complete && !boundChanged) {
      s.clampBound = 10.0f;
      boundChanged = true;
    }
  } while (!t.complete && ++calls < 5000);
  ASSERT_TRUE(t.complete);
  EXPECT_TRUE(mediumEdited);
  EXPECT_TRUE(boundChanged);
  EXPECT_GE(gbufferCalls, 2) << "the G-buffer is drawn a band per call";
  EXPECT_GE(directCalls, 8) << "the direct light is drawn a subset (and a band) per call";
  EXPECT_GE(mediaCalls, 8) << "the media are drawn a subset (and a band) per call";
  EXPECT_GE(ssbcCalls, 8) << "the compensation is drawn a draw (and a band) per call";
  std::printf("[ measured ] %d calls: direct light in %d, media in %d, compensation in %d\n", calls, directCalls,
              mediaCalls, ssbcCalls);
  PreviewRenderer whole;
  ASSERT_TRUE(whole.render(scene, vpls, s, scene.camera).complete);
  EXPECT_EQ(test::differingPixels(stepped.readLinear(), whole.readLinear()), 0u);
  EXPECT_EQ(test::differingPixels(stepped.readLinear(PreviewOutput::Scattered),
                                  whole.readLinear(PreviewOutput::Scattered)),
            0u);
}

VPLAB_GL_BACKENDS(GlMedia);

}  // namespace
}  // namespace vplab
