// The lights sidecar (renderer/scene/lights_json.h): what the editor saves comes back exactly, and a bad file is an
// error naming the key that leaves the scene as it was.

#include "renderer/scene/lights_json.h"
#include "tests/scene_test_util.h"
#include "tests/test_scenes.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace vplab {
namespace {

/// A plane with a square area light, and a point, a spot and a directional light.
Scene litPlane() {
  Scene s = test::makePlaneUnderSquareLight(2.0f, 0.25f, 1.0f, 10.0f);
  PunctualLight point, spot, sun;
  point.name = "bulb";
  point.position = glm::vec3(0.5f, 1.0f, 0.0f);
  point.intensity = glm::vec3(3.0f, 2.0f, 1.0f);
  spot.name = "spot";
  spot.type = PunctualLight::Type::Spot;
  spot.position = glm::vec3(-0.5f, 1.5f, 0.0f);
  spot.direction = glm::normalize(glm::vec3(0.2f, -1.0f, 0.0f));
  spot.innerConeAngle = 0.2f;
  spot.outerConeAngle = 0.6f;
  sun.name = "sun";
  sun.type = PunctualLight::Type::Directional;
  sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.1f));
  sun.intensity = glm::vec3(2.0f);
  s.punctualLights = {point, spot, sun};
  s.finalize();
  return s;
}

TEST(LightsJson, SavedLightsComeBackExactly) {
  Scene edited = litPlane();
  // An edit: the area light brighter and moved.
  uint32_t lightMaterial = edited.triangleMaterials[edited.emissiveTriangles[0]];
  edited.materials[lightMaterial].emission *= 2.0f;
  for (glm::vec3& p : edited.positions)
    if (p.y > 0.5f) p.x += 0.3f;
  edited.finalize();
  const std::string path = test::tmpPath("lights.json");
  saveLightsFile(path, edited);

  Scene reopened = litPlane();
  applyLightsFile(path, reopened);
  ASSERT_EQ(reopened.punctualLights.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    const PunctualLight &a = edited.punctualLights[i], &b = reopened.punctualLights[i];
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.type, b.type);
    EXPECT_EQ(a.intensity, b.intensity);
    if (!a.isDirectional()) {
      EXPECT_EQ(a.position, b.position);
    }
    EXPECT_LT(glm::length(a.direction - b.direction), 1e-6f);
    EXPECT_EQ(a.innerConeAngle, b.innerConeAngle);
    EXPECT_EQ(a.outerConeAngle, b.outerConeAngle);
  }
  ASSERT_EQ(reopened.emissiveTriangles.size(), edited.emissiveTriangles.size());
  float editedArea = 0.0f, reopenedArea = 0.0f;
  glm::vec3 editedCentre(0.0f), reopenedCentre(0.0f);
  for (uint32_t t : edited.emissiveTriangles) {
    editedArea += edited.triangleArea(t);
    for (int k = 0; k < 3; ++k) editedCentre += edited.positions[edited.triangles[t][k]];
  }
  for (uint32_t t : reopened.emissiveTriangles) {
    reopenedArea += reopened.triangleArea(t);
    for (int k = 0; k < 3; ++k) reopenedCentre += reopened.positions[reopened.triangles[t][k]];
    EXPECT_EQ(reopened.materialOf(t).emission, glm::vec3(20.0f));
    EXPECT_LT(reopened.geometricNormal(t).y, -0.999f);  // still facing down, one-sided
  }
  EXPECT_FLOAT_EQ(editedArea, reopenedArea);
  EXPECT_LT(glm::length(editedCentre - reopenedCentre), 1e-5f);
  // The plane is not a light and stays.
  EXPECT_EQ(reopened.triangles.size(), edited.triangles.size());
}

TEST(LightsJson, SidecarIsAppliedWhenItExistsAndNoted) {
  Scene s = litPlane();
  s.sourcePath = test::tmpPath("sidecar-scene.gltf");
  std::filesystem::remove(lightsSidecarPath(s.sourcePath));
  EXPECT_FALSE(applyLightsSidecar(s));
  Scene saved = s;
  saved.punctualLights.resize(1);
  saveLightsFile(lightsSidecarPath(s.sourcePath), saved);
  EXPECT_TRUE(applyLightsSidecar(s));
  EXPECT_EQ(s.punctualLights.size(), 1u);
  EXPECT_NE(s.staging.find("lights from"), std::string::npos);
}

TEST(LightsJson, BadFileNamesTheKeyAndChangesNothing) {
  Scene s = litPlane();
  const std::string path = test::tmpPath("bad-lights.json");
  test::writeText(path, R"({"punctualLights": [{"type": "point", "intensity": [1, 1, 1], "position": [0, 1e30, 0]}],
                            "areaLights": []})");
  try {
    applyLightsFile(path, s);
    FAIL() << "no error";
  } catch (const LightsJsonError& e) {
    EXPECT_NE(std::string(e.what()).find("punctualLights[0].position"), std::string::npos) << e.what();
  }
  EXPECT_EQ(s.punctualLights.size(), 3u);
  EXPECT_EQ(s.emissiveTriangles.size(), 2u);
  test::writeText(path, "[1, 2");
  EXPECT_THROW(applyLightsFile(path, s), LightsJsonError);
}

}  // namespace
}  // namespace vplab
