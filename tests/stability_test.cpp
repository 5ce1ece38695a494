// The stability suite on tiny configurations: moving the lights moves only the lights; coherent QMC VPLs flicker
// less than VPLs reshuffled every frame under a small light move; the failure maps see the clamp's energy loss; the
// grid of parameter extremes produces no non-finite or negative pixel. GlStability repeats the GL parts.

#include "evaluation/stability.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "renderer/scene/gltf_loader.h"
#include "renderer/vpl/generation_methods.h"
#include "tests/test_tmp.h"

namespace vplab {
namespace {

namespace fs = std::filesystem;

Scene cornellBox() {
  return loadScene(std::string(VPLAB_TEST_ASSETS) + "/scenes/cornell-box.gltf");
}

StabilityConfig tinyConfig(const std::string& name) {
  StabilityConfig c;
  c.outDir = vplab::test::tmpDir() + "/" + name;
  fs::remove_all(c.outDir);
  c.width = c.height = 64;
  c.frames = 3;
  c.vplCount = 32;
  c.cpuSpp = 1;
  c.referenceSpp = 8;
  c.quick = true;
  c.gl = false;
  c.writeImages = false;
  return c;
}

const FlickerRow& findRow(const std::vector<FlickerRow>& rows, const std::string& method, const std::string& mode) {
  for (const FlickerRow& r : rows)
    if (r.method == method && r.vplMode == mode) return r;
  ADD_FAILURE() << "no flicker row for " << method << " " << mode;
  return rows.front();
}

TEST(Stability, TranslateLightsMovesOnlyTheLights) {
  Scene scene = cornellBox();
  ASSERT_FALSE(scene.emissiveTriangles.empty());
  const glm::vec3 offset(0.01f, -0.02f, 0.005f);
  Scene moved = translateLights(scene, offset);
  ASSERT_EQ(moved.triangles.size(), scene.triangles.size());
  EXPECT_EQ(moved.emissiveTriangles, scene.emissiveTriangles);
  for (std::size_t t = 0; t < scene.triangles.size(); ++t) {
    bool emissive = scene.materialOf(static_cast<uint32_t>(t)).isEmissive();
    for (int k = 0; k < 3; ++k) {
      glm::vec3 before = scene.positions[scene.triangles[t][k]];
      glm::vec3 after = moved.positions[moved.triangles[t][k]];
      glm::vec3 expected = emissive ? before + offset : before;
      EXPECT_NEAR(glm::length(after - expected), 0.0f, 1e-6f) << "triangle " << t;
    }
    EXPECT_NEAR(moved.triangleArea(static_cast<uint32_t>(t)), scene.triangleArea(static_cast<uint32_t>(t)), 1e-6f);
  }
}

TEST(Stability, CoherentVplsFlickerLessThanReshuffledUnderALightMove) {
  StabilityConfig config = tinyConfig("stability_flicker");
  config.flickerMethods = {"vpl"};
  std::vector<FlickerRow> rows = measureFlicker(cornellBox(), config, "light", nullptr);
  ASSERT_EQ(rows.size(), 3u);  // reference, coherent, reshuffled
  const FlickerRow& coherent = findRow(rows, "vpl", "coherent");
  const FlickerRow& reshuffled = findRow(rows, "vpl", "reshuffled");
  EXPECT_GT(coherent.flicker, 0.0);  // the light did move
  EXPECT_EQ(coherent.perFrame.size(), 2u);
  // Measured at this size: coherent about a third of reshuffled; half leaves room for the noise of 32 VPLs.
  EXPECT_LT(coherent.flicker, 0.5 * reshuffled.flicker);
  EXPECT_LT(coherent.excess, 0.5 * reshuffled.excess);
}

// Every generation variant is a flicker method, and with a fixed seed each one moves coherently under the light
// move: light paths are Halton points, bidirectional resampling keys each candidate's selection to its own stream,
// and a Markov chain draws every step from a stream of (seed, chain, step), so a moved light changes what a step
// finds, not which random numbers it uses.
TEST(Stability, EveryGenerationMethodFlickersLessWithAFixedSeed) {
  StabilityConfig config = tinyConfig("stability_flicker_generation");
  for (const GenerationVariant& v : generationVariants()) {
    const auto& names = flickerMethodNames();
    EXPECT_NE(std::find(names.begin(), names.end(), v.name), names.end()) << v.name;
  }
  config.flickerMethods = {"reject", "bidirectional", "metropolis"};
  // Measured here: coherent 0.44 (rejection), 0.21 (bidirectional), 0.51 (Metropolis) of reshuffled. Fewer VPLs or
  // one sample per pixel let single flipped high-flux VPLs (rejection's 1/p) dominate the measure.
  config.vplCount = 128;
  config.cpuSpp = 2;
  std::vector<FlickerRow> rows = measureFlicker(cornellBox(), config, "light", nullptr);
  for (const std::string& m : config.flickerMethods) {
    const FlickerRow& coherent = findRow(rows, m, "coherent");
    const FlickerRow& reshuffled = findRow(rows, m, "reshuffled");
    EXPECT_GT(coherent.flicker, 0.0) << m;
    EXPECT_LT(coherent.flicker, 0.75 * reshuffled.flicker) << m;
  }
}

TEST(Stability, FailureMapsSeeTheClampDarkenTheImage) {
  StabilityConfig config = tinyConfig("stability_failures");
  config.writeImages = true;
  OfflineScene setup(cornellBox());
  std::vector<FailureRow> rows = failureMaps(setup, config, nullptr);
  ASSERT_EQ(rows.size(), 5u);  // vpl, clamp, vpl-kk, vsl, reject (CPU only)
  const FailureRow* vpl = nullptr;
  const FailureRow* clamp = nullptr;
  for (const FailureRow& r : rows) {
    if (r.method == "vpl (cpu)") vpl = &r;
    if (r.method == "clamp (cpu)") clamp = &r;
    EXPECT_TRUE(std::isfinite(r.relMse)) << r.method;
    EXPECT_GT(r.worstShare, 0.05) << r.method << ": error is concentrated, never evenly spread";
    EXPECT_LE(r.worstShare, 1.0);
    EXPECT_TRUE(fs::exists(config.outDir + "/" + r.heatmap)) << r.heatmap;
  }
  ASSERT_TRUE(vpl && clamp);
  // Same VPLs: the clamp only removes energy.
  EXPECT_LT(clamp->energyRatio, vpl->energyRatio);
}

TEST(Stability, CpuExtremesProduceNoBadPixels) {
  StabilityConfig config = tinyConfig("stability_extremes");
  OfflineScene setup(cornellBox());
  std::vector<ExtremeRow> rows = runExtremes(setup, config, nullptr);
  // N 0/1/large, b 0/inf for vpl and vpl-kk, r 0/huge, epsilon 0/1.
  ASSERT_EQ(rows.size(), 11u);
  for (const ExtremeRow& r : rows) {
    EXPECT_EQ(r.bad.total(), 0u) << r.parameter << " = " << r.value << " " << r.method;
    EXPECT_GE(r.timeMs, 0.0);
  }
}

TEST(GlStability, GlExtremesProduceNoBadPixels) {
  StabilityConfig config = tinyConfig("gl_stability_extremes");
  config.gl = true;
  OfflineScene setup(cornellBox());
  PreviewBench gl;
  ASSERT_TRUE(gl.available()) << gl.error();
  std::vector<ExtremeRow> rows = runExtremes(setup, config, &gl);
  std::size_t glRows = 0;
  for (const ExtremeRow& r : rows) {
    glRows += r.backend == Backend::Gl;
    EXPECT_EQ(r.bad.total(), 0u) << r.parameter << " = " << r.value << " " << r.method << " " << toString(r.backend);
  }
  // N 0/1/large, b 0/inf, r 0/huge, epsilon 0/1 as on the CPU; k 1/8, shadow map 16/2048, ssbc 0/2 x b mid/0.
  EXPECT_EQ(glRows, 17u);
}

TEST(GlStability, CoherentVplsFlickerLessInThePreview) {
  StabilityConfig config = tinyConfig("gl_stability_flicker");
  config.gl = true;
  config.flickerMethods = {"vpl-gl"};
  PreviewBench gl;
  ASSERT_TRUE(gl.available()) << gl.error();
  std::vector<FlickerRow> rows = measureFlicker(cornellBox(), config, "light", &gl);
  EXPECT_LT(findRow(rows, "vpl-gl", "coherent").flicker, 0.5 * findRow(rows, "vpl-gl", "reshuffled").flicker);
}

}  // namespace
}  // namespace vplab
