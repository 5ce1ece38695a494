// Density grids (smoke) in the GL preview (renderer/gl/media_pass.h, shaders/common/medium.glsl, docs/theory.md §22)
// on the bundled cornell-smoke scene (a 32x48x32 voxel plume): the grid as the shaders read it against the CPU's
// trilinear lookup (Medium::densityAt) and the ray-marched optical depth against a fine quadrature of it, from the 3D
// texture and from the NanoVDB buffer (renderer/gl/density_grid_storage.h), and the two storages' previews; then the
// images against the CPU on the same VPLs, as tests/gl_media_test.cpp does for homogeneous fog: the lights' single
// scattering (the CPU's forced free flights with ratio tracking), the direct light and the indirect light (the exact
// VPL render). The preview point-samples pixel centres, the CPU jitters its pixel samples: the preview is rendered at
// 4x the resolution and box-filtered down before comparing. Every GL test runs on OSMesa and on EGL.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <glm/gtc/matrix_transform.hpp>
#include <map>
#include <string>
#include <vector>

#include "renderer/core/sampling.h"
#include "renderer/gl/density_grid_storage.h"
#include "renderer/gl/gl_limits.h"
#include "renderer/gl/media_pass.h"
#include "renderer/gl/preview_renderer.h"
#include "renderer/gl/texture_units.h"
#include "renderer/image/metrics.h"
#include "renderer/offline/camera_sample.h"
#include "renderer/offline/emitter_mask.h"
#include "renderer/offline/vpl_renderer.h"
#include "renderer/scene/density_grid.h"
#include "renderer/vpl/vpl_generation.h"
#include "tests/cpu_image_cache.h"
#include "tests/gl_test_util.h"
#include "tests/media_test_util.h"
#include "tests/test_scenes.h"

namespace vplab {
namespace {

class GlSmoke : public test::GlBackendTest {};

constexpr int kUpscale = 4;
/// The compared images' size (the preview renders kUpscale x that).
constexpr int kSize = 64;

/// The preview's outputs `which` of one render at kUpscale x the settings' size, box-filtered down.
std::vector<Image> previewOutputsDownscaled(const Scene& scene, const VplSet& vpls, Settings s,
                                            const std::vector<PreviewOutput>& which) {
  s.width *= kUpscale;
  s.height *= kUpscale;
  PreviewRenderer renderer;
  renderer.render(scene, vpls, s, scene.camera);
  std::vector<Image> out;
  for (PreviewOutput w : which) out.push_back(blockAverage(renderer.readLinear(w), kUpscale));
  return out;
}

struct Comparison {
  double relMse, meanRatio;
};

/// relMSE (both images scaled to the CPU's unit mean) and mean ratio, emitters left out.
Comparison compare(const OfflineScene& l, const Image& gl, const Image& cpu, const std::string& what) {
  const PixelMask emitters = emitterMask(l.embree(), cpu.width, cpu.height, 1);
  const double scale = unitMeanScale(cpu, emitters);
  const ImageMetrics m = compareImagesExcluding(scaled(gl, scale), scaled(cpu, scale), emitters);
  const double ratio = meanRatioExcludingEmitters(gl, cpu, emitters);
  std::printf("[ measured ] %s: relMSE %.5f, mean ratio %.4f (%zu emitter pixels left out)\n", what.c_str(), m.relMse,
              ratio, emitters.count());
  EXPECT_EQ(m.nonFinitePixels, 0u) << what;
  return {m.relMse, ratio};
}

/// What shaders/test/media_probe.frag.glsl returns for segments from[i] -> to[i] and points[i] with the media `media`
/// holds: optical depth (rgb) and the grids' density (a) per probe.
std::vector<glm::vec4> probeGl(const MediaPass& media, const std::vector<glm::vec3>& from,
                               const std::vector<glm::vec3>& to, const std::vector<glm::vec3>& points) {
  const int n = static_cast<int>(points.size());
  media.bind();
  std::vector<glm::vec3> texels(from);
  texels.insert(texels.end(), to.begin(), to.end());
  texels.insert(texels.end(), points.begin(), points.end());
  GlTexture probes(n, 3, TextureFormat::Rgba32F);
  probes.uploadRgb(texels);
  probes.bind(unit(TextureUnit::PassInput0));
  ShaderProgram program({"preview/fullscreen.vert.glsl", "test/media_probe.frag.glsl"}, media.layout().defines());
  Target out(n, 1);
  out.framebuffer.bind(n, 1);
  GlVertexArray vao;
  drawFullscreen(program, vao);
  return readFramebufferRgba(out.framebuffer, 0, n, 1);
}

/// The integral of Medium::densityAt over the segment a -> b by the midpoint rule with 64 steps per voxel crossed:
/// the CPU's exact optical depth per unit sigma_t to well below the tolerances below.
double densityIntegral(const Medium& m, const glm::vec3& a, const glm::vec3& b) {
  const glm::vec3 ia = glm::vec3(m.indexFromWorld * glm::vec4(a, 1.0f));
  const glm::vec3 ib = glm::vec3(m.indexFromWorld * glm::vec4(b, 1.0f));
  const int steps = std::max(64, static_cast<int>(std::ceil(64.0f * glm::length(ib - ia))));
  double sum = 0.0;
  for (int i = 0; i < steps; ++i) sum += m.densityAt(glm::mix(a, b, (static_cast<float>(i) + 0.5f) / steps));
  return sum * glm::length(b - a) / steps;
}

struct GridErrors {
  double density, depth;  ///< worst density error (of the largest density), worst relative optical depth error
};

// The grid as the shaders read it, from its 3D texture or its NanoVDB buffer, at points inside and around the box
// against the CPU's trilinear lookup, and the ray-marched optical depth of segments across the box, and of segments
// starting inside the smoke as those toward lights and VPLs do, against a fine quadrature of that lookup.
// densityScale is set to 2.5 so that it takes part.
GridErrors gridErrorsAgainstTheCpu(bool gridInBuffer) {
  auto l = test::loadAssetScene("cornell-smoke");
  Scene scene = l->scene();
  EXPECT_EQ(scene.media.size(), 1u);
  Medium& smoke = scene.media[0];
  EXPECT_TRUE(smoke.heterogeneous());
  smoke.densityScale = 2.5f;
  Rng rng(0x736d6f6b65ull);
  auto inBox = [&](float spread) {
    const glm::vec3 q = (glm::vec3(rng.next1D(), rng.next1D(), rng.next1D()) * 2.0f - 1.0f) * spread;
    return glm::vec3(smoke.worldFromBox * glm::vec4(q, 1.0f));
  };
  const int n = 256;
  std::vector<glm::vec3> from(n), to(n), points(n);
  for (int i = 0; i < n; ++i) {
    // Half the segments cross the box from outside, half start inside it; the points reach beyond the box a little.
    from[i] = inBox(i % 2 ? 1.5f : 0.8f);
    to[i] = inBox(1.5f);
    points[i] = inBox(1.1f);
  }
  MediaPass media;
  media.upload(scene, kInfinity, gridInBuffer);
  EXPECT_EQ(media.layout().gridsInBuffer, gridInBuffer ? 1u : 0u);
  const std::vector<glm::vec4> gl = probeGl(media, from, to, points);
  const double densityMax = smoke.densityScale * smoke.density->maxValue;
  double worstDensity = 0.0, worstDepth = 0.0, meanDepth = 0.0;
  std::vector<double> cpuDepth(n);
  for (int i = 0; i < n; ++i) {
    worstDensity = std::max(worstDensity, std::abs(gl[i].a - smoke.densityAt(points[i])) / densityMax);
    cpuDepth[i] = densityIntegral(smoke, from[i], to[i]);
    meanDepth += cpuDepth[i] / n;
  }
  for (int i = 0; i < n; ++i) {
    // The depth per unit sigma_t of the green channel (all three scale the same integral), relative to the segment's
    // own, or to 1 % of the mean for the segments that barely touch the smoke.
    const double depth = gl[i].g / smoke.sigmaT().g;
    worstDepth = std::max(worstDepth, std::abs(depth - cpuDepth[i]) / std::max(cpuDepth[i], 0.01 * meanDepth));
  }
  std::printf(
      "[ measured ] cornell-smoke grid in GL from its %s: density off by at most %.2e of its maximum; optical depth "
      "(mean %.3f per unit sigma_t) off by at most %.2f %%\n",
      toString(gridInBuffer ? DensityGridStorage::Buffer : DensityGridStorage::Texture), worstDensity, meanDepth,
      100.0 * worstDepth);
  EXPECT_GT(meanDepth, 0.0);
  return {worstDensity, worstDepth};
}

// The 3D texture's linear filtering: a half-texel shift of the texture's placement would be off by far more than the
// tolerance, which allows for GPUs' 8-bit filter weights.
TEST_P(GlSmoke, GridLookupAndOpticalDepthMatchTheCpu) {
  const GridErrors e = gridErrorsAgainstTheCpu(false);
  EXPECT_LT(e.density, 4e-3);
  EXPECT_LT(e.depth, 0.02);
}

// The NanoVDB buffer read through PNanoVDB.h: the same trilinear interpolation as the CPU's in float arithmetic, so
// only rounding apart (measured: below 1e-6 of the largest density on llvmpipe).
TEST_P(GlSmoke, NanoVdbGridLookupAndOpticalDepthMatchTheCpu) {
  const GridErrors e = gridErrorsAgainstTheCpu(true);
  EXPECT_LT(e.density, 1e-5);
  EXPECT_LT(e.depth, 0.02);
}

// The preview of cornell-smoke with its grid in the NanoVDB buffer against the one with it in the 3D texture: every
// output that reads the grid (the direct light through it, the lights' and the VPLs' scattering, the gather) alike up
// to the texture's filtering precision.
TEST_P(GlSmoke, NanoVdbPreviewMatchesTheTexturePreview) {
  auto l = test::loadAssetScene("cornell-smoke");
  Settings s = test::indirectSettings(32, 16);
  s.components = Components::All;
  s.clampBound = 20.0f;
  const VplSet vpls = generateVpls(*l, s);
  auto render = [&](bool gridInBuffer) {
    Settings r = s;
    r.previewGridInBuffer = gridInBuffer;
    PreviewRenderer renderer;
    renderer.render(l->scene(), vpls, r, l->scene().camera);
    const std::vector<std::string> grids = renderer.densityGridsInUse();
    EXPECT_EQ(grids.size(), 1u);
    EXPECT_NE(grids.at(0).find(toString(gridInBuffer ? DensityGridStorage::Buffer : DensityGridStorage::Texture)),
              std::string::npos)
        << grids.at(0);
    return renderer.readLinear(PreviewOutput::Final);
  };
  const Image texture = render(false), buffer = render(true);
  const Comparison m = compare(*l, buffer, texture, "cornell-smoke preview, grid in the NanoVDB buffer vs the texture");
  std::printf("[ measured ] that relMSE: %.2e\n", m.relMse);
  EXPECT_LE(m.relMse, 1e-4);
  EXPECT_NEAR(m.meanRatio, 1.0, 1e-3);
}

// The lights' single scattering in the smoke (the preview's Scattered output without VPLs): sigma_s at each sampled
// distance from the grid, the transmittance from the camera and toward the light ray-marched.
TEST_P(GlSmoke, SingleScatteringMatchesCpu) {
  auto l = test::loadAssetScene("cornell-smoke");
  const Settings s = test::indirectSettings(kSize, 0);
  const Image gl = previewOutputsDownscaled(l->scene(), VplSet{}, s, {PreviewOutput::Scattered})[0];
  const Image& cpu = test::cachedCpu("cpuSingleScattering 256", test::renderInputs(l->scene(), s),
                                     [&] { return test::cpuSingleScattering(*l, s, 256); });
  const Comparison m = compare(*l, gl, cpu, "cornell-smoke single scattering");
  EXPECT_LE(m.relMse, 0.02);
  EXPECT_NEAR(m.meanRatio, 1.0, 0.02);
}

// The direct light through the smoke (the preview's Direct output: the surfaces' direct light, its transmittance toward
// each light sample ray-marched through the grid in the direct pass, attenuated along the camera rays, plus the lights'
// single scattering) against the CPU's (ratio tracking on every shadow ray).
TEST_P(GlSmoke, DirectLightMatchesCpu) {
  auto l = test::loadAssetScene("cornell-smoke");
  Settings s = test::indirectSettings(kSize, 0);
  s.components = Components::Direct;
  s.directLightSamples = 64;
  const Image gl = previewOutputsDownscaled(l->scene(), VplSet{}, s, {PreviewOutput::Direct})[0];
  // 256 samples per pixel: ratio tracking makes the CPU's shadow rays noisier than through fog.
  Settings c = s;
  c.samplesPerPixel = 256;
  const Image& cpu = test::cachedVplRender(*l, VplSet{}, Method::Vpl, c);
  const Comparison m = compare(*l, gl, cpu, "cornell-smoke direct light");
  EXPECT_LE(m.relMse, 0.02);
  EXPECT_NEAR(m.meanRatio, 1.0, 0.02);
}

// The indirect light (the gather attenuated along camera rays, with the transmittance toward each VPL through the
// grid, plus the VPLs' in-scattering with sigma_s from the grid) against the CPU's exact VPL render on the same VPLs,
// surface and medium ones. The smoke is thin: a few % of the VPLs land in it, and their in-scattering along the camera
// rays is a few % of the image.
TEST_P(GlSmoke, IndirectMatchesCpu) {
  auto l = test::loadAssetScene("cornell-smoke");
  Settings s = test::indirectSettings(kSize, 128);
  s.clampBound = 20.0f;
  const VplSet vpls = generateVpls(*l, s);
  std::size_t inMedium = 0;
  for (const Vpl& v : vpls.vpls) inMedium += v.inMedium;
  ASSERT_GT(inMedium, 0u) << "no medium VPLs to test";
  const std::vector<Image> gl =
      previewOutputsDownscaled(l->scene(), vpls, s, {PreviewOutput::Indirect, PreviewOutput::Scattered});
  Settings c = s;
  c.samplesPerPixel = 32;
  const Image& cpu = test::cachedVplRender(*l, vpls, Method::Vpl, c);
  const Comparison m = compare(*l, gl[0], cpu,
                               "cornell-smoke indirect, " + std::to_string(vpls.vpls.size()) + " VPLs (" +
                                   std::to_string(inMedium) + " in the smoke), b = 20");
  EXPECT_LE(m.relMse, 0.02);
  EXPECT_NEAR(m.meanRatio, 1.0, 0.02);
  const double scattered = meanLuminance(gl[1]) - meanLuminance(previewOutputsDownscaled(
                                                      l->scene(), VplSet{}, s, {PreviewOutput::Scattered})[0]);
  std::printf("[ measured ] cornell-smoke: the VPLs' in-scattering is %.1f %% of the indirect mean\n",
              100.0 * scattered / meanLuminance(gl[0]));
  // More than the mean may be off by: without it the comparison above would fail.
  EXPECT_GT(scattered, 0.03 * meanLuminance(gl[0]));
}

// Several grid media (kPreviewMaxDensityGrids): cornell-smoke's room and light with its plume replaced by two
// procedural grids of their own sizes, densities and coefficients. `alongRays` false: a 24^3 ball of smoke left of the
// room's middle and a 16^3 ramp right of it, on pixels of their own; true: a thin 16^3 haze reaching from behind the
// camera (which it holds) into the room, and the ball behind it, so that every camera ray through the ball crosses the
// haze first. With `dropSecond` the second grid neither absorbs nor scatters, so the preview leaves it out (what the
// bounds below must catch); the media keep their indices, which medium VPLs refer to.
std::unique_ptr<OfflineScene> twoGridScene(bool alongRays, bool dropSecond = false) {
  Scene scene = test::loadAssetScene("cornell-smoke")->scene();
  scene.media.clear();
  const glm::vec3 ballCentre = alongRays ? glm::vec3(0.2f, 0.43f, 0.3f) : glm::vec3(0.15f, 0.38f, 0.2f);
  const float radius = 0.1f;
  Medium ball = test::gridMedium(
      ballCentre - radius, ballCentre + radius, glm::ivec3(24),
      [&](const glm::vec3& p) {
        return std::max(0.0f, 1.0f - glm::dot(p - ballCentre, p - ballCentre) / (radius * radius));
      },
      glm::vec3(1.0f), glm::vec3(8.0f, 9.0f, 10.0f), 0.3f);
  ball.name = "ball";
  Medium second;
  if (alongRays) {
    const glm::vec3 lower(0.04f, 0.04f, -0.95f), upper(0.52f, 0.52f, 0.05f);
    second = test::gridMedium(
        lower, upper, glm::ivec3(16),
        [&](const glm::vec3& p) { return 0.6f + 0.4f * (p.x - lower.x) / (upper.x - lower.x); }, glm::vec3(0.05f),
        glm::vec3(0.4f, 0.45f, 0.5f), -0.2f);
    second.name = "haze";
  } else {
    const glm::vec3 lower(0.33f, 0.36f, 0.1f), upper(0.51f, 0.5f, 0.3f);
    second = test::gridMedium(
        lower, upper, glm::ivec3(16), [&](const glm::vec3& p) { return (p.y - lower.y) / (upper.y - lower.y); },
        glm::vec3(0.5f), glm::vec3(6.0f, 5.0f, 4.0f), -0.2f);
    second.name = "ramp";
  }
  if (dropSecond) second.sigmaA = second.sigmaS = glm::vec3(0.0f);
  // The haze first: the grids' order in the table is not the order along the rays.
  if (alongRays) scene.media.push_back(second);
  scene.media.push_back(ball);
  if (!alongRays) scene.media.push_back(second);
  EXPECT_EQ(mediaProblem(scene.media), "");
  return std::make_unique<OfflineScene>(std::move(scene));
}

// The two grids' lookups and optical depths as the shaders read them against the CPU's (as
// GridLookupAndOpticalDepthMatchTheCpu for one), on segments from the haze (some from the camera) through the ball:
// from their textures, from one NanoVDB buffer, after an edit of the first grid, which re-uploads that grid alone and,
// in the buffer, moves the second within the GPU, and from one storage each.
TEST_P(GlSmoke, TwoGridsLookupsAndOpticalDepthsMatchTheCpu) {
  auto l = twoGridScene(true);
  Scene scene = l->scene();
  Rng rng(0x74776f67726964ull);
  auto inBox = [&](const Medium& m, float spread) {
    const glm::vec3 q = (glm::vec3(rng.next1D(), rng.next1D(), rng.next1D()) * 2.0f - 1.0f) * spread;
    return glm::vec3(m.worldFromBox * glm::vec4(q, 1.0f));
  };
  const int n = 128;
  std::vector<glm::vec3> from(n), to(n), points(n);
  for (int i = 0; i < n; ++i) {
    from[i] = i % 4 == 0 ? scene.camera.position : inBox(scene.media[0], 0.9f);
    to[i] = inBox(scene.media[1], 1.2f);
    points[i] = inBox(scene.media[i % 2], 1.05f);
  }
  auto check = [&](const MediaPass& media, const std::string& what) {
    const std::vector<glm::vec4> gl = probeGl(media, from, to, points);
    double worstDensity = 0.0, worstDepth = 0.0;
    for (int i = 0; i < n; ++i) {
      double density = 0.0, depth = 0.0;
      for (const Medium& m : scene.media) {
        const glm::vec3 inBoxCoords = glm::vec3(m.boxFromWorld * glm::vec4(points[i], 1.0f));
        if (glm::all(glm::lessThanEqual(glm::abs(inBoxCoords), glm::vec3(1.0f)))) density += m.densityAt(points[i]);
        depth += m.sigmaT().g * densityIntegral(m, from[i], to[i]);
      }
      worstDensity = std::max(worstDensity, std::abs(gl[i].a - density));
      worstDepth = std::max(worstDepth, std::abs(gl[i].g - depth) / depth);
    }
    std::printf("[ measured ] two grids from %s: density off by at most %.2e, optical depth by at most %.2f %%\n",
                what.c_str(), worstDensity, 100.0 * worstDepth);
    EXPECT_LT(worstDensity, 4e-3) << what;
    EXPECT_LT(worstDepth, 0.02) << what;
  };
  // The haze's box, where its replacements below go.
  const glm::vec3 lower = glm::vec3(scene.media[0].worldFromBox * glm::vec4(-1.0f, -1.0f, -1.0f, 1.0f));
  const glm::vec3 upper = glm::vec3(scene.media[0].worldFromBox * glm::vec4(1.0f, 1.0f, 1.0f, 1.0f));
  auto hazeOf = [&](glm::ivec3 voxels) {
    const Medium& haze = l->scene().media[0];
    return test::gridMedium(
        lower, upper, voxels, [&](const glm::vec3& p) { return 0.5f + 0.5f * (p.y - lower.y) / (upper.y - lower.y); },
        haze.sigmaA, haze.sigmaS, haze.g);
  };
  for (bool inBuffer : {false, true}) {
    MediaPass media;
    media.upload(scene, kInfinity, inBuffer);
    EXPECT_EQ(media.layout().gridMedia, (std::vector<int>{0, 1}));
    EXPECT_EQ(media.layout().gridsInBuffer, inBuffer ? 3u : 0u);
    EXPECT_EQ(media.grids().uploads(), 2);
    check(media, inBuffer ? "one NanoVDB buffer" : "3D textures");
    // A new density scale changes the table only; a new first grid (a finer haze, so a larger NanoVDB grid) is the
    // one upload.
    scene.media[1].densityScale = 1.5f;
    media.upload(scene, kInfinity, inBuffer);
    EXPECT_EQ(media.grids().uploads(), 2);
    scene.media[0] = hazeOf(glm::ivec3(20));
    media.upload(scene, kInfinity, inBuffer);
    EXPECT_EQ(media.grids().uploads(), 3);
    check(media, std::string(inBuffer ? "one NanoVDB buffer" : "3D textures") + ", the first grid replaced");
    scene = l->scene();
  }
  // The first grid longer than this context's 3D textures, so in the buffer, the second in its texture: each read
  // from its own storage.
  const int maxSide = queryGlLimits().max3dTextureSize;
  scene.media[0] = hazeOf(glm::ivec3(4, 4, maxSide + 1));
  MediaPass media;
  media.upload(scene, kInfinity, false);
  EXPECT_EQ(media.layout().gridsInBuffer, 1u);
  check(media, "a NanoVDB buffer and a 3D texture (" + std::to_string(maxSide + 1) + " voxels long)");
}

/// The two-grid images' size: a quarter of kSize's pixels, at the same bounds (the preview renders kUpscale x that).
constexpr int kTwoGridSize = 32;

/// The lights' single scattering of a two-grid scene in the preview (Scattered, no VPLs) and on the CPU (as
/// SingleScatteringMatchesCpu for one grid), and the preview of the scene without its second grid against the same CPU
/// image: that comparison must fail the bound the first passes.
void expectTwoGridScatteringMatchesCpu(bool alongRays) {
  auto l = twoGridScene(alongRays);
  const Settings s = test::indirectSettings(kTwoGridSize, 0);
  const std::string what = alongRays ? "two grids along camera rays" : "two grids side by side";
  const Image gl = previewOutputsDownscaled(l->scene(), VplSet{}, s, {PreviewOutput::Scattered})[0];
  const Image& cpu = test::cachedCpu("cpuSingleScattering 256", test::renderInputs(l->scene(), s),
                                     [&] { return test::cpuSingleScattering(*l, s, 256); });
  const Comparison m = compare(*l, gl, cpu, what + ", single scattering");
  EXPECT_LE(m.relMse, 0.02);
  EXPECT_NEAR(m.meanRatio, 1.0, 0.02);
  const Image oneGrid =
      previewOutputsDownscaled(twoGridScene(alongRays, true)->scene(), VplSet{}, s, {PreviewOutput::Scattered})[0];
  const Comparison dropped = compare(*l, oneGrid, cpu, what + ", the second grid left out of the preview");
  EXPECT_TRUE(dropped.relMse > 0.02 || std::abs(dropped.meanRatio - 1.0) > 0.02);
}

TEST_P(GlSmoke, TwoGridsSingleScatteringMatchesCpu) {
  expectTwoGridScatteringMatchesCpu(false);
}

// The camera inside the first grid, the second behind it: each camera ray's transmittance is the product of both
// marches, and the lights' scattering in the second is attenuated by the first.
TEST_P(GlSmoke, TwoGridsAlongCameraRaysSingleScatteringMatchesCpu) {
  expectTwoGridScatteringMatchesCpu(true);
}

// The indirect light of the side-by-side grids on the same VPLs as the CPU's exact VPL render (as IndirectMatchesCpu
// for one grid): medium VPLs in both grids, sigma_s of each grid where the VPLs' light scatters, the transmittance
// toward each VPL through both; the preview without the second grid fails the bounds.
TEST_P(GlSmoke, TwoGridsIndirectMatchesCpu) {
  auto l = twoGridScene(false);
  Settings s = test::indirectSettings(kTwoGridSize, 128);
  s.clampBound = 20.0f;
  const VplSet vpls = generateVpls(*l, s);
  std::size_t inMedium[2] = {0, 0};
  for (const Vpl& v : vpls.vpls) inMedium[v.medium] += v.inMedium;
  ASSERT_GT(inMedium[0], 0u) << "no medium VPLs in the first grid";
  ASSERT_GT(inMedium[1], 0u) << "no medium VPLs in the second grid";
  const Image gl = previewOutputsDownscaled(l->scene(), vpls, s, {PreviewOutput::Indirect})[0];
  Settings c = s;
  c.samplesPerPixel = 32;
  const Image& cpu = test::cachedVplRender(*l, vpls, Method::Vpl, c);
  const Comparison m =
      compare(*l, gl, cpu,
              "two grids, indirect, " + std::to_string(vpls.vpls.size()) + " VPLs (" + std::to_string(inMedium[0]) +
                  " and " + std::to_string(inMedium[1]) + " in the grids), b = 20");
  EXPECT_LE(m.relMse, 0.02);
  EXPECT_NEAR(m.meanRatio, 1.0, 0.02);
  const Image oneGrid =
      previewOutputsDownscaled(twoGridScene(false, true)->scene(), vpls, s, {PreviewOutput::Indirect})[0];
  const Comparison dropped = compare(*l, oneGrid, cpu, "two grids, indirect, the second grid left out of the preview");
  EXPECT_TRUE(dropped.relMse > 0.02 || std::abs(dropped.meanRatio - 1.0) > 0.02);
}

VPLAB_GL_BACKENDS(GlSmoke);

// A grid goes to the NanoVDB buffer where a side exceeds the context's 3D textures, where its texture would exceed
// kMaxDensityTextureBytes, or when asked to; else to the 3D texture.
TEST(SmokePreviewFit, GridStorageFollowsTheTextureLimits) {
  auto l = test::loadAssetScene("cornell-smoke");
  const DensityGrid& grid = *l->scene().media[0].density;
  const int largestSide = std::max({grid.size.x, grid.size.y, grid.size.z});
  EXPECT_EQ(densityGridStorage(grid, largestSide, false), DensityGridStorage::Texture);
  EXPECT_EQ(densityGridStorage(grid, largestSide - 1, false), DensityGridStorage::Buffer);
  EXPECT_EQ(densityGridStorage(grid, 2048, true), DensityGridStorage::Buffer);
  DensityGrid tall;
  tall.size = glm::ivec3(1024, 1024, 65);  // 260 MiB of R32F
  EXPECT_EQ(densityGridStorage(tall, 2048, false), DensityGridStorage::Buffer);
}

// The preview draws up to kPreviewMaxDensityGrids density grids: one more is refused with a sentence that says so,
// before any GL work.
TEST(SmokePreviewFit, RefusesWhatThePreviewCannotDraw) {
  auto l = test::loadAssetScene("cornell-smoke");
  Scene scene = l->scene();
  const Medium plume = scene.media[0];
  for (int i = 1; i <= kPreviewMaxDensityGrids; ++i) {
    EXPECT_EQ(mediaFitProblem(scene), "") << i << " grids";
    Medium next = plume;
    next.setBox(glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, 10.0f * i)) * plume.worldFromBox);
    scene.media.push_back(next);
  }
  EXPECT_EQ(mediaFitProblem(scene),
            "the scene holds 5 media with density grids; the preview draws at most 4: merge the "
            "grids into one, or use vplab render");
}

// The lights' single scattering marches toward an area light kMediaLightSteps times per pixel however many of its
// samples the pixel takes: the distances are spread over them, one at least each.
TEST(SmokePreviewFit, AreaLightSamplesShareTheScatteringDistances) {
  EXPECT_EQ(kMediaLightSteps, 4);
  EXPECT_EQ(areaLightSteps(64, 16), 1);  // 4 samples per pixel (64 samples, k = 4)
  EXPECT_EQ(areaLightSteps(32, 16), 2);  // 2 samples
  EXPECT_EQ(areaLightSteps(48, 16), 2);  // 3 samples: at least kMediaLightSteps distances in all
  EXPECT_EQ(areaLightSteps(16, 16), 4);  // 1 sample
  EXPECT_EQ(areaLightSteps(8, 16), 4);   // half the subsets take one sample, the others none
  EXPECT_EQ(areaLightSteps(64, 1), 1);   // 64 samples per pixel (k = 1)
  EXPECT_EQ(areaLightSteps(0, 16), kMediaLightSteps);
}

}  // namespace
}  // namespace vplab
