// Textured emitters (docs/methods.md, "Textured emitters") on a glTF file built here: a floor under a panel whose
// emissive texture is black on one half and white on the other (test::TexturedPanel). The light sampler, the
// reference and the exact VPL render are checked against the closed form (the preview in tests/gl_direct_test.cpp):
// the panel's underside shows the texture, and the floor receives the white half's polygon irradiance only.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "renderer/core/sampling.h"
#include "renderer/offline/light_sampler.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/offline/path_tracer.h"
#include "renderer/offline/vpl_renderer.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/lights_json.h"
#include "renderer/vpl/vpl_generation.h"
#include "tests/scene_test_util.h"
#include "tests/test_scenes.h"

namespace vplab {
namespace {

using test::TexturedPanel;

const Material& panelMaterial(const Scene& s) {
  for (const Material& m : s.materials)
    if (m.name == "panel") return m;
  throw std::runtime_error("no panel material");
}

TEST(EmissiveTexture, LoaderReadsTextureTimesFactorTimesStrength) {
  Scene s = loadScene(TexturedPanel::write("textured-panel.gltf"));
  for (const std::string& w : s.warnings) EXPECT_EQ(w.find("emissive"), std::string::npos) << w;
  const Material& m = panelMaterial(s);
  ASSERT_GE(m.emissiveTexture, 0);
  EXPECT_EQ(s.emissiveTriangles.size(), 32u);
  // Per triangle: the left half's triangles emit nothing on average, the right half's the full radiance (the
  // columns next to x = 0 carry the texture's one-texel blend).
  for (uint32_t t : s.emissiveTriangles) {
    const glm::uvec3& v = s.triangles[t];
    const float cx = (s.positions[v.x].x + s.positions[v.y].x + s.positions[v.z].x) / 3.0f;
    const glm::vec3 mean = s.meanEmission(t);
    if (cx < -0.25f) {
      EXPECT_EQ(mean.r, 0.0f);
    }
    if (cx > 0.25f) {
      EXPECT_NEAR(mean.r, TexturedPanel::kPanelRadiance.r, 1e-4f);
    }
    if (cx > 0.0f) {
      EXPECT_NEAR(mean.g, TexturedPanel::kPanelRadiance.g, 0.01f * TexturedPanel::kPanelRadiance.g);
    }
    const glm::vec2 centre = s.uvAt(t, glm::vec2(1.0f / 3.0f));
    EXPECT_NEAR(s.emissionAt(s.triangleMaterials[t], centre).b, TexturedPanel::panelRadiance(cx).b, 1e-4f);
  }
}

// The loader bakes the base colour's KHR_texture_transform into the UVs; the emissive texture must still be read at
// its own coordinates (its own transform, if any, applied to the file's TEXCOORD_0).
TEST(EmissiveTexture, KeepsItsOwnTextureTransform) {
  auto emissionAtFileUv = [](nlohmann::json baseTransform, nlohmann::json emissiveTransform) {
    test::GltfBuilder b;
    b.doc["extensionsUsed"] = {"KHR_texture_transform"};
    // Texel 0 (u < 0.5) white, texel 1 black; every corner at u = 0.25, the white texel's centre.
    test::writeBytes(test::tmpPath("emissive-transform.bmp"), test::bmp(2, 1, {{255, 255, 255}, {0, 0, 0}}));
    b.doc["images"] = {{{"uri", "emissive-transform.bmp"}}};
    b.doc["textures"] = {{{"source", 0}}};
    nlohmann::json base = {{"index", 0}}, emissive = {{"index", 0}};
    if (!baseTransform.is_null()) base["extensions"] = {{"KHR_texture_transform", baseTransform}};
    if (!emissiveTransform.is_null()) emissive["extensions"] = {{"KHR_texture_transform", emissiveTransform}};
    int material = b.push("materials", {{"pbrMetallicRoughness", {{"baseColorTexture", base}}},
                                        {"emissiveFactor", {1.0, 1.0, 1.0}},
                                        {"emissiveTexture", emissive}});
    nlohmann::json prim = test::GltfBuilder::primitive(b.vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}), -1, -1, material);
    prim["attributes"]["TEXCOORD_0"] = b.vec2({{0.25f, 0.5f}, {0.25f, 0.5f}, {0.25f, 0.5f}});
    b.meshNode(b.mesh({prim}));
    Scene s = loadScene(b.writeGltf("emissive-transform.gltf"));
    return s.emissionAt(s.triangleMaterials[0], s.uvAt(0, glm::vec2(1.0f / 3.0f))).g;
  };
  const nlohmann::json shift = {{"offset", {0.5, 0.0}}};
  EXPECT_NEAR(emissionAtFileUv(nullptr, nullptr), 1.0f, 1e-5f);
  EXPECT_NEAR(emissionAtFileUv(shift, nullptr), 1.0f, 1e-5f) << "the base colour's transform moved the emission";
  EXPECT_NEAR(emissionAtFileUv(nullptr, shift), 0.0f, 1e-5f) << "the emissive texture's own transform is ignored";
  EXPECT_NEAR(emissionAtFileUv(shift, shift), 0.0f, 1e-5f);
}

TEST(EmissiveTexture, EmitterPowerIsTheTexturedPowerAndSamplesLieOnTheWhiteHalf) {
  OfflineScene offline(loadScene(TexturedPanel::write("textured-panel.gltf")));
  const LightSampler& lights = offline.lights();
  // pi x radiance x the white half's area (0.5 m^2); the blend across x = 0 is symmetric and adds nothing.
  const glm::vec3 expected = kPi * 0.5f * TexturedPanel::kPanelRadiance;
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(lights.totalPower()[c], expected[c], 1e-3f * expected[c]) << c;

  // Light tracing starts on the white half only (within the blend's 2 mm), and its weights average to the power.
  const int n = 4096;
  glm::dvec3 weightSum(0.0);
  int onWhite = 0;
  for (int i = 0; i < n; ++i) {
    Rng rng(hashKey(3, static_cast<uint64_t>(i)));
    float u = (static_cast<float>(i) + 0.5f) / n;
    EmissionSample e = lights.sampleEmission(u, rng.next2D(), rng.next2D());
    ASSERT_TRUE(e.valid);
    ASSERT_GE(e.position.x, -0.01f) << "an emission sample on the black half";
    onWhite += e.position.x > 0.0f ? 1 : 0;
    weightSum += glm::dvec3(e.weight);
  }
  EXPECT_GE(onWhite, n * 99 / 100);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(weightSum[c] / n, expected[c], 0.01 * expected[c]) << c;
}

TEST(EmissiveTexture, ReferenceMatchesClosedForm) {
  OfflineScene offline(loadScene(TexturedPanel::write("textured-panel.gltf")));
  Settings s;
  s.width = s.height = 32;
  s.samplesPerPixel = 128;
  s.threads = 2;
  Image reference = renderReference(offline, s).image;
  TexturedPanel::expectClosedForm(reference, offline.scene().camera, 0.002, 0.01, 0.01, "reference");
}

TEST(EmissiveTexture, ExactVplRenderAndVplFluxFollowTheTexture) {
  OfflineScene offline(loadScene(TexturedPanel::write("textured-panel.gltf")));
  Settings s = test::smallVplSettings(32, 4000);
  s.samplesPerPixel = 128;
  s.vplMaxBounces = 1;
  VplSet set = generateVpls(offline, s);
  // The flux the VPLs bring to the floor, per half, against the closed-form irradiance integrated over it.
  double fluxLeft = 0.0, fluxRight = 0.0;
  for (const Vpl& v : set.vpls) {
    if (std::abs(v.position.y) > 1e-3f) continue;
    (v.position.x < 0.0f ? fluxLeft : fluxRight) += v.flux.r;
  }
  const glm::dvec3 white[4] = {{0.0, 0.5, -0.5}, {0.5, 0.5, -0.5}, {0.5, 0.5, 0.5}, {0.0, 0.5, 0.5}};
  const int cells = 200;
  double expectedLeft = 0.0, expectedRight = 0.0;
  for (int j = 0; j < cells; ++j)
    for (int i = 0; i < cells; ++i) {
      glm::dvec3 x(-1.0 + 2.0 * (i + 0.5) / cells, 0.0, -1.0 + 2.0 * (j + 0.5) / cells);
      double e = test::polygonIrradiance(x, {0, 1, 0}, white, 4, TexturedPanel::kPanelRadiance.r) * (4.0 / (cells * cells));
      (x.x < 0.0 ? expectedLeft : expectedRight) += e;
    }
  std::printf("[ measured ] VPL flux on the floor: left %.4f (closed form %.4f), right %.4f (%.4f)\n", fluxLeft,
              expectedLeft, fluxRight, expectedRight);
  EXPECT_NEAR(fluxLeft, expectedLeft, 0.04 * expectedLeft);
  EXPECT_NEAR(fluxRight, expectedRight, 0.02 * expectedRight);

  // The exact VPL render: the panel seen directly and the floor's direct light (nothing here is lit indirectly, so
  // a few VPLs do).
  s.vplCount = 64;
  Image image = renderVpl(offline, generateVpls(offline, s), Method::Vpl, s).image;
  TexturedPanel::expectClosedForm(image, offline.scene().camera, 0.002, 0.01, 0.01, "exact VPL render");
}

TEST(EmissiveTexture, LightsSidecarKeepsTheTextureCoordinates) {
  Scene s = loadScene(TexturedPanel::write("textured-panel.gltf"));
  const glm::vec3 power = LightSampler(s).totalPower();
  const std::string path = test::tmpPath("textured-panel.lights.json");
  saveLightsFile(path, s);
  applyLightsFile(path, s);
  ASSERT_EQ(s.emissiveTriangles.size(), 32u);
  const glm::vec3 reloaded = LightSampler(s).totalPower();
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(reloaded[c], power[c], 1e-4f * power[c]) << c;
}

}  // namespace
}  // namespace vplab
