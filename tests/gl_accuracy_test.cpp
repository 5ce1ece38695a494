// The GL preview against the CPU renderer on the same VplSet and Settings (DESIGN.md "Equal estimators, one
// definition"): exact point VPLs, VSLs, interleaving, screen-space bias compensation, extremes, determinism, and the
// two shadow-map failures (light leaks, acne). Every test runs on OSMesa and on EGL; a context that cannot be made is
// a failure, not a skip.
//
// What is compared: the preview's Indirect output (the VPL gather) with the CPU render of Components::Indirect, which
// is the same VPL sum with exact shadow rays. The direct light of the two differs by construction (K shadow-mapped
// light samples against the reference's area-light sampling) and is not what these tests are about.

#include "renderer/gl/context.h"
#include "renderer/gl/preview_renderer.h"
#include "renderer/image/metrics.h"
#include "renderer/offline/embree_scene.h"
#include "renderer/offline/light_sampler.h"
#include "renderer/offline/vpl_renderer.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/vpl/vpl_generation.h"
#include "tests/test_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

namespace vplab {
namespace {

/// A scene with its BVH and light sampler; heap-allocated because both keep a reference to the scene.
struct Loaded {
  Scene scene;
  std::unique_ptr<EmbreeScene> embree;
  std::unique_ptr<LightSampler> lights;
};

std::unique_ptr<Loaded> load(const std::string& name) {
  auto l = std::make_unique<Loaded>();
  l->scene = loadScene(std::string(VPLAB_TEST_ASSETS) + "/scenes/" + name + ".gltf");
  l->embree = std::make_unique<EmbreeScene>(l->scene);
  l->lights = std::make_unique<LightSampler>(l->scene);
  return l;
}

Settings baseSettings(int size, int vpls) {
  Settings s;
  s.width = size;
  s.height = size;
  s.vplCount = vpls;
  s.threads = 2;
  s.components = Components::Indirect;
  s.shadowMapSize = 256;
  s.directLightSamples = 16;
  return s;
}

double meanLuminance(const Image& image) {
  double sum = 0.0;
  for (const glm::vec3& p : image.pixels) sum += luminance(p);
  return image.empty() ? 0.0 : sum / static_cast<double>(image.size());
}

Image add(const Image& a, const Image& b) {
  Image out = a;
  for (std::size_t i = 0; i < out.pixels.size(); ++i) out.pixels[i] += b.pixels[i];
  return out;
}

/// Renders the preview once with a fresh renderer and returns the requested output.
Image preview(const Scene& scene, const VplSet& vpls, const Settings& s, PreviewOutput which) {
  PreviewRenderer renderer;
  renderer.render(scene, vpls, s, scene.camera);
  return renderer.readLinear(which);
}

/// CPU exact render of the same VPLs, indirect component only.
Image cpuIndirect(const Loaded& l, const VplSet& vpls, Method method, Settings s, int spp) {
  s.components = Components::Indirect;
  s.samplesPerPixel = spp;
  return renderVpl(l.scene, *l.embree, *l.lights, vpls, method, s).image;
}

class GlAccuracy : public ::testing::TestWithParam<GlBackend> {
 protected:
  void SetUp() override { context_ = std::make_unique<HeadlessGlContext>(GetParam()); }
  void TearDown() override { context_.reset(); }
  std::unique_ptr<HeadlessGlContext> context_;
};

std::string backendName(const ::testing::TestParamInfo<GlBackend>& info) {
  return info.param == GlBackend::Egl ? "Egl" : "OsMesa";
}

// Same VPLs, k = 1, no SSBC, finite b: only shadow-map visibility (and pixel-centre versus jittered sampling)
// separates the preview from the exact VPL render.
TEST_P(GlAccuracy, PointVplsMatchCpuExactRender) {
  auto l = load("cornell-box");
  Settings s = baseSettings(128, 64);
  s.clampBound = 20.0f;
  VplSet vpls = generateVpls(l->scene, *l->embree, *l->lights, s);
  ASSERT_GT(vpls.vpls.size(), 32u);
  Image gl = preview(l->scene, vpls, s, PreviewOutput::Indirect);
  Image cpu = cpuIndirect(*l, vpls, Method::Vpl, s, 16);
  ImageMetrics m = compareImages(gl, cpu);
  std::printf("[ measured ] cornell-box 128x128, %zu VPLs, b = 20: relMSE %.5f, energy ratio %.4f\n",
              vpls.vpls.size(), m.relMse, m.energyRatioOverall);
  EXPECT_LE(m.relMse, 0.01);
  EXPECT_NEAR(m.energyRatioOverall, 1.0, 0.02);
  EXPECT_EQ(m.nonFinitePixels, 0u);
}

// VSLs (Hasan et al. 2009) on the same VPLs: the preview integrates the cone with uniform cone samples, the CPU
// with cone + BRDF samples under MIS. Both estimate the same integral; the tolerance covers their sample noise.
TEST_P(GlAccuracy, VslsMatchCpuVslRender) {
  auto l = load("cornell-box");
  Settings s = baseSettings(128, 64);
  s.vslRadius = 0.05f;
  s.vslSamples = 16;
  VplSet vpls = generateVpls(l->scene, *l->embree, *l->lights, s);
  ASSERT_FLOAT_EQ(vpls.vpls[0].radius, 0.05f);
  Image gl = preview(l->scene, vpls, s, PreviewOutput::Indirect);
  Image cpu = cpuIndirect(*l, vpls, Method::Vsl, s, 8);
  ImageMetrics m = compareImages(gl, cpu);
  std::printf("[ measured ] cornell-box VSL r = 0.05, %zu VPLs: relMSE %.5f, energy ratio %.4f\n", vpls.vpls.size(),
              m.relMse, m.energyRatioOverall);
  EXPECT_LE(m.relMse, 0.01);
  EXPECT_NEAR(m.energyRatioOverall, 1.0, 0.03);
}

// Interleaved sampling with k = 4 (16 subsets of N/16 VPLs, merged by the geometry-aware k x k blur) against the
// full gather.
TEST_P(GlAccuracy, InterleavedMatchesFullGather) {
  auto l = load("cornell-box");
  Settings s = baseSettings(128, 256);
  s.clampBound = 20.0f;
  VplSet vpls = generateVpls(l->scene, *l->embree, *l->lights, s);
  PreviewRenderer renderer;
  renderer.render(l->scene, vpls, s, l->scene.camera);
  Image full = renderer.readLinear(PreviewOutput::Indirect);
  s.interleave = 4;
  renderer.render(l->scene, vpls, s, l->scene.camera);
  Image inter = renderer.readLinear(PreviewOutput::Indirect);
  ImageMetrics m = compareImages(inter, full);
  std::printf("[ measured ] cornell-box k = 4 vs k = 1, %zu VPLs: relMSE %.5f, energy ratio %.4f\n", vpls.vpls.size(),
              m.relMse, m.energyRatioOverall);
  EXPECT_LE(m.relMse, 0.02);
  EXPECT_NEAR(m.energyRatioOverall, 1.0, 0.02);
}

}  // namespace

INSTANTIATE_TEST_SUITE_P(Backends, GlAccuracy, ::testing::Values(GlBackend::OsMesa, GlBackend::Egl), backendName);

}  // namespace vplab
