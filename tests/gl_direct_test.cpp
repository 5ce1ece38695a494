// The preview's direct light (one shadow map per emitter or punctual light, renderer/gl/light_shadows.h) against the
// path-traced reference's direct component. The preview point-samples pixel centres while the reference box-filters
// each pixel, which matters along the emitter's and the shadows' edges: the preview is rendered at 4x the resolution
// and box-filtered down before comparing. OSMesa and EGL.

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>

#include "renderer/gl/context.h"
#include "renderer/gl/preview_renderer.h"
#include "renderer/image/metrics.h"
#include "renderer/offline/path_tracer.h"
#include "renderer/scene/gltf_loader.h"
#include "tests/gl_test_util.h"
#include "tests/test_scenes.h"

namespace vplab {
namespace {

class GlDirect : public test::GlBackendTest {};

// Preview direct light (Le seen directly included, as the reference's direct component has it) at 4x, box-filtered,
// against the reference's direct component.
ImageMetrics directAgainstReference(const OfflineScene& l, int size, int referenceSpp, const char* name,
                                    Image* previewOut = nullptr) {
  Settings s;
  s.width = s.height = 4 * size;
  s.threads = 2;
  s.directLightSamples = 64;
  PreviewRenderer renderer;
  renderer.render(l.scene(), VplSet{}, s, l.scene().camera);
  // With no VPLs the final image is Le + direct.
  Image preview = blockAverage(renderer.readLinear(PreviewOutput::Final), 4);
  Settings r = s;
  r.width = r.height = size;
  r.samplesPerPixel = referenceSpp;
  r.components = Components::Direct;
  Image reference = renderReference(l, r).image;
  ImageMetrics m = compareImages(preview, reference);
  std::printf("[ measured ] %s direct light, preview at %d^2 box-filtered to %d^2 vs reference %d spp: relMSE %.5f, "
              "energy %.4f\n",
              name, 4 * size, size, referenceSpp, m.relMse, m.energyRatioOverall);
  EXPECT_EQ(m.nonFinitePixels, 0u);
  if (previewOut) *previewOut = preview;
  return m;
}

TEST_P(GlDirect, AreaLightMatchesReferenceCornellBox) {
  auto l = test::loadAssetScene("cornell-box");
  ImageMetrics m = directAgainstReference(*l, 64, 1024, "cornell-box");
  EXPECT_LE(m.relMse, 0.005);
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
  Scene scene = test::loadAssetScene("cornell-box")->scene();
  for (Material& m : scene.materials) m.emission = glm::vec3(0.0f);
  // Drop the ceiling so that the sun reaches the floor.
  std::vector<glm::uvec3> triangles;
  std::vector<uint32_t> materials;
  for (std::size_t t = 0; t < scene.triangles.size(); ++t) {
    const glm::uvec3& v = scene.triangles[t];
    bool ceiling = scene.positions[v.x].y > 0.5f && scene.positions[v.y].y > 0.5f && scene.positions[v.z].y > 0.5f;
    if (ceiling) continue;
    triangles.push_back(v);
    materials.push_back(scene.triangleMaterials[t]);
  }
  scene.triangles = triangles;
  scene.triangleMaterials = materials;
  PunctualLight sun;
  sun.name = "sun";
  sun.type = PunctualLight::Type::Directional;
  sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.4f));
  sun.intensity = glm::vec3(2.0f);
  scene.punctualLights.push_back(sun);
  scene.finalize();
  OfflineScene l(std::move(scene));
  ImageMetrics m = directAgainstReference(l, 64, 64, "cornell-box without ceiling, directional light");
  EXPECT_LE(m.relMse, 0.02);
  EXPECT_NEAR(m.energyRatioOverall, 1.0, 0.02);
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

}  // namespace

VPLAB_GL_BACKENDS(GlDirect);

}  // namespace vplab
