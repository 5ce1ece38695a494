// Staging (renderer/scene/staging.h): when the studio is added, what it is made of, and that it scales with the
// model. The real third-party files are in third_party_scenes_test.cpp.

#include "renderer/core/sampling.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/staging.h"
#include "tests/test_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace vplab {
namespace {

/// A unit cube of white Lambert faces centred at `center` with side `side`, no lights, the loader's automatic
/// camera and its "no lights" warning, as loadScene() would leave a model without lights.
Scene unlitCube(glm::vec3 center = glm::vec3(0.0f), float side = 1.0f) {
  Scene s;
  s.sourcePath = "cube-in-code";
  uint32_t white = test::addLambertMaterial(s, glm::vec3(0.7f));
  test::addCube(s, center, 0.5f * side, white, false);
  s.finalize();
  s.camera.position = center + glm::vec3(0.0f, 0.0f, 3.0f * side);
  s.warnings.push_back(kNoLightsWarning);
  return s;
}

TEST(Staging, AutoStagesOnlyASceneWithoutLights) {
  Scene unlit = unlitCube();
  stageScene(unlit, Stage::Auto);
  EXPECT_TRUE(unlit.hasLights());
  EXPECT_NE(unlit.staging.find("auto"), std::string::npos) << unlit.staging;
  // The warning that the image will be black no longer applies.
  EXPECT_EQ(std::count(unlit.warnings.begin(), unlit.warnings.end(), std::string(kNoLightsWarning)), 0);

  Scene lit = test::makePlaneUnderPointLight(2.0f, glm::vec3(0.0f, 1.0f, 0.0f), 5.0f);
  const std::size_t triangles = lit.triangles.size();
  stageScene(lit, Stage::Auto);
  EXPECT_EQ(lit.triangles.size(), triangles);
  EXPECT_TRUE(lit.staging.empty());
}

TEST(Staging, NoneNeverStudioAlways) {
  Scene unlit = unlitCube();
  stageScene(unlit, Stage::None);
  EXPECT_FALSE(unlit.hasLights());
  EXPECT_TRUE(unlit.staging.empty());
  EXPECT_EQ(std::count(unlit.warnings.begin(), unlit.warnings.end(), std::string(kNoLightsWarning)), 1);

  Scene lit = test::makePlaneUnderPointLight(2.0f, glm::vec3(0.0f, 1.0f, 0.0f), 5.0f);
  const std::size_t triangles = lit.triangles.size();
  stageScene(lit, Stage::Studio);
  EXPECT_GT(lit.triangles.size(), triangles);
  EXPECT_EQ(lit.punctualLights.size(), 1u);  // the file's own light stays
  EXPECT_NE(lit.staging.find("studio"), std::string::npos) << lit.staging;
}

TEST(Staging, ModelStandsOnTheGroundLitByALightFacingIt) {
  const glm::vec3 center(1.0f, 2.0f, -3.0f);
  Scene s = unlitCube(center);
  const Bounds model = s.geometryBounds;
  stageScene(s, Stage::Auto);
  ASSERT_EQ(s.emissiveTriangles.size(), 2u);

  // The ground: upward-facing triangles at the model's lowest y, reaching well beyond the model on every side.
  Bounds ground;
  for (uint32_t t = 0; t < s.triangles.size(); ++t)
    if (s.geometricNormal(t).y > 0.999f && s.materialOf(t).name == "studio")
      for (int k = 0; k < 3; ++k) ground.extend(s.positions[s.triangles[t][k]]);
  ASSERT_TRUE(ground.valid());
  EXPECT_NEAR(ground.lower.y, model.lower.y, 1e-6f);
  EXPECT_NEAR(ground.upper.y, model.lower.y, 1e-6f);
  EXPECT_LT(ground.lower.x, model.lower.x - 1.0f);
  EXPECT_GT(ground.upper.x, model.upper.x + 1.0f);

  // The light faces the model's centre and gives it an irradiance of pi (a white surface facing it: L = 1).
  uint32_t tri = s.emissiveTriangles[0];
  glm::vec3 n = s.geometricNormal(tri);
  glm::dvec3 corners[4];
  int count = 0;
  for (uint32_t t : s.emissiveTriangles)
    for (int k = 0; k < 3 && count < 4; ++k) {
      glm::dvec3 p(s.positions[s.triangles[t][k]]);
      if (std::none_of(corners, corners + count, [&](const glm::dvec3& q) { return glm::length(p - q) < 1e-9; }))
        corners[count++] = p;
    }
  ASSERT_EQ(count, 4);
  // Order the four corners around their centre for the polygon formula.
  glm::dvec3 mid = 0.25 * (corners[0] + corners[1] + corners[2] + corners[3]);
  glm::vec3 toModel = glm::normalize(center - glm::vec3(mid));
  EXPECT_GT(glm::dot(n, toModel), 0.999f);
  glm::dvec3 e1 = glm::normalize(corners[0] - mid), e2 = glm::cross(glm::dvec3(n), e1);
  std::sort(corners, corners + 4, [&](const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::dot(a - mid, e2), glm::dot(a - mid, e1)) < std::atan2(glm::dot(b - mid, e2), glm::dot(b - mid, e1));
  });
  double e = test::polygonIrradiance(glm::dvec3(center), -glm::dvec3(toModel), corners, 4, s.materialOf(tri).emission.g);
  EXPECT_NEAR(e, kPi, 1e-3 * kPi);

  // The automatic camera looks at the model.
  EXPECT_FALSE(s.camera.fromFile);
  EXPECT_GT(glm::dot(glm::normalize(center - s.camera.position), s.camera.forward), 0.9999f);
}

TEST(Staging, ScalesWithTheModelAndIsDeterministic) {
  Scene small = unlitCube(glm::vec3(0.0f), 0.01f), large = unlitCube(glm::vec3(0.0f), 100.0f);
  stageScene(small, Stage::Auto);
  stageScene(large, Stage::Auto);
  ASSERT_EQ(small.positions.size(), large.positions.size());
  for (std::size_t i = 0; i < small.positions.size(); ++i)
    ASSERT_LT(glm::length(small.positions[i] * 1e4f - large.positions[i]), 1e-3f * 100.0f) << i;
  EXPECT_NEAR(small.materialOf(small.emissiveTriangles[0]).emission.g,
              large.materialOf(large.emissiveTriangles[0]).emission.g, 1e-3f);
  Scene again = unlitCube(glm::vec3(0.0f), 0.01f);
  stageScene(again, Stage::Auto);
  EXPECT_EQ(again.positions, small.positions);
  EXPECT_EQ(again.staging, small.staging);
}

}  // namespace
}  // namespace vplab
