// The lights sidecar (renderer/scene/lights_json.h): what the editor saves comes back exactly, and a bad file is an
// error naming the key that leaves the scene as it was.

#include "renderer/scene/lights_json.h"
#include "tests/scene_test_util.h"
#include "tests/test_scenes.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

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

/// A rotated fog box and a second, axis-aligned one beside it.
std::vector<Medium> twoFogBoxes() {
  Medium a, b;
  a.name = "haze";
  a.sigmaA = glm::vec3(0.1f, 0.2f, 0.3f);
  a.sigmaS = glm::vec3(1.5f, 1.25f, 0.75f);
  a.g = -0.4f;
  glm::mat4 world(1.0f);
  world[0] = glm::vec4(0.3f, 0.0f, 0.4f, 0.0f);  // half size 0.5 along (0.6, 0, 0.8)
  world[1] = glm::vec4(0.0f, 0.25f, 0.0f, 0.0f);
  world[2] = glm::vec4(-0.16f, 0.0f, 0.12f, 0.0f);
  world[3] = glm::vec4(-0.5f, 0.5f, 0.0f, 1.0f);
  a.setBox(world);
  b = a;
  b.name = "mist";
  b.g = 0.7f;
  b.setBox(glm::mat4(glm::vec4(0.2f, 0, 0, 0), glm::vec4(0, 0.2f, 0, 0), glm::vec4(0, 0, 0.2f, 0),
                     glm::vec4(1.0f, 0.5f, 0.0f, 1.0f)));
  return {a, b};
}

TEST(LightsJson, SavedMediaComeBackExactlyAndAFileWithoutMediaKeepsTheScenes) {
  Scene edited = litPlane();
  edited.media = twoFogBoxes();
  const std::string path = test::tmpPath("media.lights.json");
  saveLightsFile(path, edited);
  Scene reopened = litPlane();
  applyLightsFile(path, reopened);
  ASSERT_EQ(reopened.media.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const Medium& a = edited.media[i];
    const Medium& b = reopened.media[i];
    EXPECT_EQ(b.name, a.name);
    EXPECT_EQ(b.sigmaA, a.sigmaA);
    EXPECT_EQ(b.sigmaS, a.sigmaS);
    EXPECT_EQ(b.g, a.g);
    EXPECT_EQ(b.fillsSpace, a.fillsSpace);
    EXPECT_EQ(b.worldFromBox, a.worldFromBox);
    EXPECT_EQ(b.boxFromWorld, a.boxFromWorld);
  }
  // Fog everywhere has no box.
  Medium space = edited.media[0];
  space.fillsSpace = true;
  edited.media = {space};
  saveLightsFile(path, edited);
  applyLightsFile(path, reopened);
  ASSERT_EQ(reopened.media.size(), 1u);
  EXPECT_TRUE(reopened.media[0].fillsSpace);
  EXPECT_EQ(lightsToJson(reopened), lightsToJson(edited));
  // A sidecar written before media were edited (no "media" key) leaves the scene's media alone.
  test::writeText(path, R"({"punctualLights": [], "areaLights": []})");
  applyLightsFile(path, reopened);
  EXPECT_EQ(reopened.media.size(), 1u);
}

TEST(LightsJson, BadMediaNameTheKeyAndChangeNothing) {
  Scene s = litPlane();
  s.media = twoFogBoxes();
  const nlohmann::json good = nlohmann::json::parse(lightsToJson(s));
  const std::string path = test::tmpPath("bad-media.json");
  struct Case {
    std::function<void(nlohmann::json&)> spoil;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {[](nlohmann::json& j) { j["media"][0]["g"] = 1.0; }, "media[0]: medium 'haze': g must lie in (-1, 1)"},
      {[](nlohmann::json& j) { j["media"][0]["g"] = "forward"; }, "media[0].g"},
      {[](nlohmann::json& j) { j["media"][1]["fillsSpace"] = 3; }, "media[1].fillsSpace"},
      {[](nlohmann::json& j) { j["media"][0].erase("name"); }, "media[0]: missing 'name'"},
      {[](nlohmann::json& j) { j["media"][0]["sigmaA"][0] = -0.5; }, "sigmaA.r must lie in [0,"},
      {[](nlohmann::json& j) { j["media"][0]["sigmaS"][2] = 1e30; }, "media[0].sigmaS"},
      {[](nlohmann::json& j) { j["media"][0]["sigmaS"] = {1, 2}; }, "media[0].sigmaS: expected 3 numbers"},
      {[](nlohmann::json& j) { j["media"][1]["worldFromBox"].erase(0); }, "media[1].worldFromBox: expected 16"},
      {[](nlohmann::json& j) { j["media"][1]["worldFromBox"][0] = 0.0; }, "the box has no volume"},
      {[](nlohmann::json& j) { j["media"] = "fog"; }, "media: expected an array"},
      // The second box moved onto the first: boxes must not overlap.
      {[](nlohmann::json& j) { j["media"][1]["worldFromBox"][12] = -0.5; }, "medium boxes overlap"},
      // A medium filling all space beside a box.
      {[](nlohmann::json& j) { j["media"][1]["fillsSpace"] = true; },
       "cannot lie inside the medium that fills all space"},
  };
  for (const Case& c : cases) {
    nlohmann::json spoiled = good;
    c.spoil(spoiled);
    test::writeText(path, spoiled.dump(2));
    const std::string before = lightsToJson(s);
    try {
      applyLightsFile(path, s);
      ADD_FAILURE() << "no error for " << c.expected;
    } catch (const LightsJsonError& e) {
      EXPECT_NE(std::string(e.what()).find(c.expected), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).rfind(path, 0), 0u) << e.what();
    }
    EXPECT_EQ(lightsToJson(s), before) << "a bad file must change nothing: " << c.expected;
  }
}

}  // namespace
}  // namespace vplab
