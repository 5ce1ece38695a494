// The preview's direct light (one shadow map per emitter or punctual light, renderer/gl/light_shadows.h) against the
// path-traced reference's direct component. The preview point-samples pixel centres while the reference box-filters
// each pixel, which matters along the emitter's and the shadows' edges: the preview is rendered at 4x the resolution
// and box-filtered down before comparing. OSMesa and EGL.

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>

#include "evaluation/direct_light_cases.h"
#include "renderer/gl/context.h"
#include "renderer/gl/preview_renderer.h"
#include "renderer/image/metrics.h"
#include "renderer/offline/emitter_mask.h"
#include "renderer/offline/path_tracer.h"
#include "renderer/offline/progressive.h"
#include "renderer/scene/gltf_loader.h"
#include "tests/cpu_image_cache.h"
#include "tests/gl_test_util.h"
#include "tests/test_scenes.h"

namespace vplab {
namespace {

class GlDirect : public test::GlBackendTest {};

// Preview direct light (Le seen directly included, as the reference's direct component has it) at 4x, box-filtered,
// against the reference's direct component; over the pixels `excluded` keeps (emitterMask at size x size: the
// emitters, exact in both, would otherwise hold most of the energy) or over all.
ImageMetrics directAgainstReference(const OfflineScene& l, int size, int referenceSpp, const char* name,
                                    Image* previewOut = nullptr, const PixelMask* excluded = nullptr,
                                    int interleave = 1) {
  Settings s;
  s.width = s.height = 4 * size;
  s.threads = 2;
  s.directLightSamples = 64;
  s.interleave = interleave;
  PreviewRenderer renderer;
  renderer.render(l.scene(), VplSet{}, s, l.scene().camera);
  // With no VPLs the final image is Le + direct.
  Image preview = blockAverage(renderer.readLinear(PreviewOutput::Final), 4);
  Settings r = s;
  r.width = r.height = size;
  r.samplesPerPixel = referenceSpp;
  r.components = Components::Direct;
  r.interleave = 1;  // the reference ignores it: one image for every k
  const Image& reference = test::cachedReference(l, r);
  ImageMetrics m = excluded ? compareImagesExcluding(preview, reference, *excluded) : compareImages(preview, reference);
  std::printf(
      "[ measured ] %s direct light, preview at %d^2 box-filtered to %d^2 vs reference %d spp%s: relMSE %.5f, "
      "energy %.4f\n",
      name, 4 * size, size, referenceSpp, excluded ? ", emitters excluded" : "", m.relMse, m.energyRatioOverall);
  EXPECT_EQ(m.nonFinitePixels, 0u);
  if (previewOut) *previewOut = preview;
  return m;
}

// The Cornell box without its ceiling, so that a directional light reaches the floor; with or without the emitter
// just below the ceiling.
Scene openCornellBox(bool keepEmitter) {
  Scene scene = test::loadAssetScene("cornell-box")->scene();
  std::vector<glm::uvec3> triangles;
  std::vector<uint32_t> materials;
  for (std::size_t t = 0; t < scene.triangles.size(); ++t) {
    const glm::uvec3& v = scene.triangles[t];
    bool ceiling = scene.positions[v.x].y > 0.5f && scene.positions[v.y].y > 0.5f && scene.positions[v.z].y > 0.5f;
    bool emitter = scene.materials[scene.triangleMaterials[t]].emission != glm::vec3(0.0f);
    if (ceiling && !(emitter && keepEmitter)) continue;
    triangles.push_back(v);
    materials.push_back(scene.triangleMaterials[t]);
  }
  scene.triangles = triangles;
  scene.triangleMaterials = materials;
  return scene;
}

TEST_P(GlDirect, AreaLightMatchesReferenceCornellBox) {
  auto l = test::loadAssetScene("cornell-box");
  const PixelMask emitters = emitterMask(l->embree(), 64, 64);
  // The emitter holds 69 % of this image's energy: compared over all pixels, lit surfaces 5-6 % too dark passed.
  // Measured with the emitter and its edge excluded: relMSE 0.00020, mean ratio 0.9979 (both backends; with one
  // soft-shadow map per emitter filtered by a disc 0.9644 and 0.0015). Bounds: 1 +- 0.01, relMSE 0.001.
  ImageMetrics m = directAgainstReference(*l, 64, 1024, "cornell-box", nullptr, &emitters);
  EXPECT_LE(m.relMse, 0.001);
  EXPECT_NEAR(m.energyRatioOverall, 1.0, 0.01);
}

// The same at the editor's interleave k = 4: each pixel takes the area light's samples of its subset and its k x k
// block shares one blocker search (preview/blocker_search.frag.glsl), and the de-interleave blends the subsets back.
// Measured (both backends): relMSE 0.00029, mean ratio 1.0002; the same bounds as at k = 1.
TEST_P(GlDirect, AreaLightAtInterleaveFourMatchesReferenceCornellBox) {
  auto l = test::loadAssetScene("cornell-box");
  const PixelMask emitters = emitterMask(l->embree(), 64, 64);
  ImageMetrics m = directAgainstReference(*l, 64, 1024, "cornell-box, k = 4", nullptr, &emitters, 4);
  EXPECT_LE(m.relMse, 0.001);
  EXPECT_NEAR(m.energyRatioOverall, 1.0, 0.01);
}

// A 40 x 40 cm emitter under the box's 55 cm ceiling, close to the walls and the blocks: one soft-shadow map filtered
// by a disc of the emitter's radius reached behind the emitter and found the ceiling, and the room was 16 % too dark.
// Measured (emitters excluded, 32^2, 512 spp): mean 1.0135, relMSE 0.0015 on both backends (1.009 at 64^2, where fewer
// pixels mix the emitter's edge); bounds 1 +- 0.025 and 0.004.
TEST_P(GlDirect, LargeAreaLightCloseToGeometryMatchesReference) {
  OfflineScene l(cornellWithLargeEmitter(std::string(VPLAB_ASSET_DIR) + "/scenes/cornell-box.gltf", 0.4f));
  const PixelMask emitters = emitterMask(l.embree(), 32, 32);
  ImageMetrics m = directAgainstReference(l, 32, 512, "cornell-box, 40 cm emitter", nullptr, &emitters);
  EXPECT_LE(m.relMse, 0.004);
  EXPECT_NEAR(m.energyRatioOverall, 1.0, 0.025);
}

// The walls' top band of the Cornell box, at the horizon of the emitter 0.5 mm under the ceiling: the textbook
// soft-shadow filter gave these pixels half their light or less. Compared over the wall pixels whose primary hit lies
// within 5 cm below the emitter's plane (216 pixels). Measured (64^2, 1024 spp): mean 1.0136, relMSE 3e-5.
TEST_P(GlDirect, WallsAtTheEmitterHorizonGetTheirLight) {
  auto l = test::loadAssetScene("cornell-box");
  const Scene& scene = l->scene();
  float emitterY = std::numeric_limits<float>::max();
  for (uint32_t t : scene.emissiveTriangles)
    for (int k = 0; k < 3; ++k) emitterY = std::min(emitterY, scene.positions[scene.triangles[t][k]].y);
  const int size = 64;
  PixelMask outsideBand(size, size);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const glm::vec3 d = cameraRayDirection(scene.camera, x + 0.5f, y + 0.5f, size, size);
      const std::optional<SurfaceHit> hit = l->embree().intersect(scene.camera.position, d);
      const bool inBand = hit && std::abs(hit->geometricNormal.y) < 0.5f && hit->position.y < emitterY &&
                          hit->position.y > emitterY - 0.05f;
      outsideBand.at(x, y) = inBand ? 0 : 1;
    }
  const std::size_t bandPixels = outsideBand.excluded.size() - outsideBand.count();
  ASSERT_GT(bandPixels, 100u);
  ImageMetrics m = directAgainstReference(*l, size, 1024, "cornell-box walls within 5 cm of the emitter's horizon",
                                          nullptr, &outsideBand);
  std::printf("[ measured ] %zu band pixels\n", bandPixels);
  EXPECT_NEAR(m.energyRatioOverall, 1.0, 0.03);
}

// Debian's 2CylinderEngine (110k triangles, millimetre units, its own camera with z_near = 5 cm), every material
// Lambert, under a point light: the cooling fins shadow each other a texel or two apart, and the camera's depth range
// needs reversed depth in the G-buffer (with GL's usual depth the top plate lost pixels to the part beneath it: mean
// 0.949 at 64^2). Measured (32^2, 64 spp): mean 0.9942, relMSE 0.0075, most of it the reference's noise.
TEST_P(GlDirect, DetailedLambertModelUnderPointLightMatchesReference) {
  const std::string engine = "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";
  if (!std::filesystem::exists(engine)) GTEST_SKIP() << engine << " is not installed (Debian's assimp-testmodels)";
  Scene scene = loadScene(engine);
  makeLambert(scene);
  addPointLightAbove(scene);
  OfflineScene l(std::move(scene));
  ImageMetrics m = directAgainstReference(l, 32, 64, "2CylinderEngine, Lambert, point light");
  EXPECT_LE(m.relMse, 0.015);
  EXPECT_NEAR(m.energyRatioOverall, 1.0, 0.02);
}

// A finely detailed model lit by a point light: the bumpy sphere's relief shadows itself, where acne and stair-steps
// would show.
TEST_P(GlDirect, PointLightMatchesReferenceOnDetailedModel) {
  Scene scene = test::denseCornellScene(20000);
  // Replace the area light by a point light beside the sphere (it lights the relief at every angle).
  for (Material& m : scene.materials) m.emission = glm::vec3(0.0f);
  PunctualLight p;
  p.name = "point";
  p.position = glm::vec3(0.15f, 0.5f, 0.15f);
  p.intensity = glm::vec3(1.2f, 0.8f, 0.2f);
  scene.punctualLights.push_back(p);
  scene.finalize();
  OfflineScene l(std::move(scene));
  ImageMetrics m = directAgainstReference(l, 64, 64, "cornell-box + 20k-triangle sphere, point light");
  EXPECT_LE(m.relMse, 0.02);
  EXPECT_NEAR(m.energyRatioOverall, 1.0, 0.02);
}

// The Cornell box under a sun through where its ceiling would be: the blocks' shadows on the floor from a
// directional light's orthographic map, against the reference.
TEST_P(GlDirect, DirectionalLightMatchesReference) {
  OfflineScene l(cornellUnderSun(std::string(VPLAB_ASSET_DIR) + "/scenes/cornell-box.gltf"));
  // Measured: relMSE 0.00141, mean 0.9963 (both backends; the map's texels at the blocks' shadow edges).
  ImageMetrics m = directAgainstReference(l, 64, 64, "cornell-box without ceiling, directional light");
  EXPECT_LE(m.relMse, 0.003);
  EXPECT_NEAR(m.energyRatioOverall, 1.0, 0.01);
}

// A glTF panel whose emissive texture is black on one half and white on the other (test::TexturedPanel): the
// preview's camera-seen emission and direct light against the reference and against the closed form.
TEST_P(GlDirect, TexturedEmitterMatchesReferenceAndClosedForm) {
  OfflineScene l(loadScene(test::TexturedPanel::write("textured-panel.glb")));
  Image preview;
  ImageMetrics m = directAgainstReference(l, 32, 256, "textured panel", &preview);
  EXPECT_LE(m.relMse, 0.005);
  EXPECT_NEAR(m.energyRatioOverall, 1.0, 0.02);
  test::TexturedPanel::expectClosedForm(preview, l.scene().camera, 0.005, 0.02, 0.03, "preview, textured panel");
}

// A plane lit at 80 degrees from its normal by a point light: every pixel is lit (nothing occludes), so any pixel
// darker than the unshadowed light is shadow acne.
TEST_P(GlDirect, GrazingPlaneShowsNoAcne) {
  Scene scene;
  uint32_t mat = test::addLambertMaterial(scene, glm::vec3(0.5f));
  test::addQuad(scene, {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, mat, {0, 0, 1});
  scene.camera.position = glm::vec3(0, 0, 3);
  scene.camera.forward = glm::vec3(0, 0, -1);
  scene.camera.up = glm::vec3(0, 1, 0);
  scene.camera.yfov = 0.75f;
  PunctualLight p;
  p.position = glm::vec3(-4.0f, 0.0f, 4.0f * std::tan(glm::radians(10.0f)));
  p.intensity = glm::vec3(10.0f);
  scene.punctualLights.push_back(p);
  scene.finalize();
  Settings s;
  s.width = s.height = 128;
  PreviewRenderer renderer;
  renderer.render(scene, VplSet{}, s, scene.camera);
  Image direct = renderer.readLinear(PreviewOutput::Direct);
  int lit = 0, dark = 0;
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128; ++x) {
      glm::vec2 ndc((x + 0.5f) / 128.0f * 2.0f - 1.0f, 1.0f - (y + 0.5f) / 128.0f * 2.0f);
      glm::vec3 d = scene.camera.rayDirection(ndc, 1.0f);
      glm::vec3 x1 = scene.camera.position + d * (-scene.camera.position.z / d.z);
      if (std::abs(x1.x) > 0.98f || std::abs(x1.y) > 0.98f) continue;
      glm::vec3 w = p.position - x1;
      float dist2 = glm::dot(w, w);
      float expected = 0.5f / 3.14159265f * 10.0f * (w.z / std::sqrt(dist2)) / dist2;
      ++lit;
      dark += direct.at(x, y).g < 0.98f * expected;
    }
  std::printf("[ measured ] grazing point light (80 degrees): %d lit pixels, %d darker than unshadowed\n", lit, dark);
  ASSERT_GT(lit, 10000);
  EXPECT_EQ(dark, 0);
}

// The direct pass draws its lights in runs that share one shadow map, each kind of map (area emitter, punctual light,
// directional light) with its own program (renderer/gl/direct_pass.h): an open Cornell box lit by two area emitters, a
// point, a spot and a directional light gives the sum of the images of its lights drawn alone.
// The open Cornell box with its emitter and a second, smaller one facing down near the left wall.
Scene openBoxWithTwoEmitters() {
  Scene open = openCornellBox(true);
  uint32_t lamp = test::addLambertMaterial(open, glm::vec3(0.5f), glm::vec3(4.0f, 6.0f, 8.0f));
  test::addQuad(open, {0.45f, 0.35f, 0.1f}, {0.5f, 0.35f, 0.1f}, {0.5f, 0.35f, 0.2f}, {0.45f, 0.35f, 0.2f}, lamp,
                {0, -1, 0});
  return open;
}

/// A point, a spot and a directional light for openBoxWithTwoEmitters().
std::vector<PunctualLight> punctualLightOfEachKind() {
  std::vector<PunctualLight> punctual(3);
  punctual[0].name = "point";
  punctual[0].position = glm::vec3(0.15f, 0.3f, 0.2f);
  punctual[0].intensity = glm::vec3(0.2f, 0.1f, 0.05f);
  punctual[1].name = "spot";
  punctual[1].type = PunctualLight::Type::Spot;
  punctual[1].position = glm::vec3(0.3f, 0.45f, 0.3f);
  punctual[1].direction = glm::vec3(0.0f, -1.0f, 0.0f);
  punctual[1].innerConeAngle = 0.3f;
  punctual[1].outerConeAngle = 0.5f;
  punctual[1].intensity = glm::vec3(0.1f, 0.3f, 0.2f);
  punctual[2].name = "sun";
  punctual[2].type = PunctualLight::Type::Directional;
  punctual[2].direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.4f));
  punctual[2].intensity = glm::vec3(1.0f);
  return punctual;
}

Settings smallDirectSettings() {
  Settings s;
  s.width = s.height = 64;
  s.directLightSamples = 48;
  return s;
}

TEST_P(GlDirect, LightsOfEveryKindAddUp) {
  const Scene open = openBoxWithTwoEmitters();
  const std::vector<PunctualLight> punctual = punctualLightOfEachKind();
  // The direct light of `scene` with the lights picked: the emitters, and the punctual lights whose bits are set.
  auto render = [&](bool emitters, unsigned lights) {
    Scene scene = open;
    if (!emitters)
      for (Material& m : scene.materials) m.emission = glm::vec3(0.0f);
    for (std::size_t i = 0; i < punctual.size(); ++i)
      if (lights & (1u << i)) scene.punctualLights.push_back(punctual[i]);
    scene.finalize();
    PreviewRenderer renderer;
    renderer.render(scene, VplSet{}, smallDirectSettings(), scene.camera);
    return renderer.readLinear(PreviewOutput::Direct);
  };
  Image all = render(true, 7u);
  Image sum = render(true, 0u);
  for (unsigned i = 0; i < punctual.size(); ++i) {
    Image alone = render(false, 1u << i);
    double energy = 0.0;
    for (std::size_t p = 0; p < sum.pixels.size(); ++p) {
      sum.pixels[p] += alone.pixels[p];
      energy += alone.pixels[p].r + alone.pixels[p].g + alone.pixels[p].b;
    }
    EXPECT_GT(energy, 1.0) << punctual[i].name << " lights nothing";
  }
  ImageMetrics m = compareImages(all, sum);
  std::printf(
      "[ measured ] two emitters + point + spot + sun against the sum of each alone: relMSE %.3g, energy %.7f\n",
      m.relMse, m.energyRatioOverall);
  EXPECT_EQ(m.nonFinitePixels, 0u);
  EXPECT_LE(m.relMse, 1e-9);
  EXPECT_NEAR(m.energyRatioOverall, 1.0, 1e-5);
}

// Settings::lightShadowMapSize sizes every kind of light map (area cells, point and spot cubes, the sun's square): at
// 128 instead of 1024 the shadows' edges move by the coarser texels and the energy stays. Measured: relMSE 0.0030,
// energy 1.0025 on both backends. Bounds: 0.01, 1 +- 0.02.
TEST_P(GlDirect, LightShadowMapSizeSizesEveryKindOfMap) {
  Scene scene = openBoxWithTwoEmitters();
  scene.punctualLights = punctualLightOfEachKind();
  scene.finalize();
  Settings s = smallDirectSettings();
  PreviewRenderer renderer;
  renderer.render(scene, VplSet{}, s, scene.camera);
  const Image fine = renderer.readLinear(PreviewOutput::Direct);
  s.lightShadowMapSize = 128;
  renderer.render(scene, VplSet{}, s, scene.camera);
  const Image coarse = renderer.readLinear(PreviewOutput::Direct);
  ImageMetrics m = compareImages(coarse, fine);
  std::printf("[ measured ] light maps at 128 against 1024: relMSE %.4g, energy %.4f, %zu pixels differ\n", m.relMse,
              m.energyRatioOverall, test::differingPixels(coarse, fine));
  EXPECT_GT(test::differingPixels(coarse, fine), 0u) << "the size did not reach the maps";
  EXPECT_EQ(m.nonFinitePixels, 0u);
  EXPECT_LE(m.relMse, 0.01);
  EXPECT_NEAR(m.energyRatioOverall, 1.0, 0.02);
}

// Punctual lights are drawn at every pixel and added after the merge (shaders/preview/direct.frag.glsl): with k x k
// interleaving, and with the indirect light on a coarser grid, a point light's direct light is the one of k = 1, where
// interleaving it gave one pixel in k^2 its light and the merge 4-pixel stair-steps along its shadows.
TEST_P(GlDirect, PunctualLightsAreNotInterleaved) {
  Scene scene = test::denseCornellScene(2000);
  for (Material& m : scene.materials) m.emission = glm::vec3(0.0f);
  PunctualLight p;
  p.position = glm::vec3(0.15f, 0.5f, 0.15f);
  p.intensity = glm::vec3(1.2f, 0.8f, 0.2f);
  scene.punctualLights.push_back(p);
  scene.finalize();
  // With no VPLs the final image is the direct light.
  auto render = [&](int interleave, int downscale) {
    Settings s;
    s.width = s.height = 64;
    s.interleave = interleave;
    s.indirectDownscale = downscale;
    PreviewRenderer renderer;
    renderer.render(scene, VplSet{}, s, scene.camera);
    return renderer.readLinear(PreviewOutput::Final);
  };
  Image every = render(1, 1);
  for (auto [k, s] : {std::pair{4, 1}, std::pair{4, 2}, std::pair{3, 2}}) {
    ImageMetrics m = compareImages(render(k, s), every);
    std::printf("[ measured ] point light, k = %d, s = %d against k = 1: relMSE %.3g\n", k, s, m.relMse);
    EXPECT_LE(m.relMse, 1e-9) << "k = " << k << ", s = " << s;
  }
}

}  // namespace

VPLAB_GL_BACKENDS(GlDirect);

}  // namespace vplab
