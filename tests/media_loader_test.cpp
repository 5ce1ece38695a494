// Participating media in glTF files (extension VPLAB_participating_media, docs/scenes.md): boxes under their node's
// world transform, a medium filling all space, one error per kind of bad input naming its glTF path, the bundled fog
// scenes, and what `vplab info` prints about them.

#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/staging.h"
#include "tests/scene_test_util.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>

namespace vplab {
namespace {

using test::loadError;
using nlohmann::json;
using test::GltfBuilder;

constexpr const char* kExt = "VPLAB_participating_media";

std::string asset(const std::string& name) {
  return std::string(VPLAB_TEST_ASSETS) + "/scenes/" + name + ".gltf";
}

/// A floor quad and a light far below it: the least a file needs to load without warnings, plus the medium
/// extension declared as used.
GltfBuilder baseScene() {
  GltfBuilder b;
  int pos = b.vec3({{-5, 0, -5}, {5, 0, -5}, {5, 0, 5}, {-5, 0, 5}});
  int idx = b.indicesU16({0, 2, 1, 0, 3, 2});
  b.meshNode(b.mesh({GltfBuilder::primitive(pos, idx)}));  // node 0
  b.addLightQuad();                                         // node 1
  b.doc["extensionsUsed"] = {kExt};
  return b;
}

/// `medium` with one more field.
json with(json medium, const char* key, json value) {
  medium[key] = std::move(value);
  return medium;
}

json fog(json sigmaA = {0.1, 0.2, 0.3}, json sigmaS = {1.0, 2.0, 3.0}) {
  return {{"sigmaA", sigmaA}, {"sigmaS", sigmaS}};
}

/// A node without a mesh carrying the extension; returns its index.
int mediumNode(GltfBuilder& b, const std::string& name, json medium, json transform = json::object()) {
  json n = transform;
  n["name"] = name;
  n["extensions"] = {{kExt, std::move(medium)}};
  return b.node(n);
}

void expectVec3Eq(const glm::vec3& a, const glm::vec3& b) {
  EXPECT_FLOAT_EQ(a.x, b.x);
  EXPECT_FLOAT_EQ(a.y, b.y);
  EXPECT_FLOAT_EQ(a.z, b.z);
}

// --- valid files ------------------------------------------------------------------------------------------------

TEST(MediaLoader, BoxFollowsItsNodesWorldTransform) {
  GltfBuilder b = baseScene();
  // A parent moves the box 10 m along x: the box is [-1, 1]^3 under the child's world transform.
  json medium = fog();
  medium["g"] = 0.3;
  int child = b.node({{"name", "fog"},
                      {"translation", {1, 2, 3}},
                      {"scale", {0.5, 1, 2}},
                      {"extensions", {{kExt, medium}}}},
                     false);
  b.node({{"name", "parent"}, {"translation", {10, 0, 0}}, {"children", {child}}});
  Scene s = loadScene(b.writeGltf("box.gltf"));
  ASSERT_EQ(s.media.size(), 1u);
  const Medium& m = s.media[0];
  EXPECT_EQ(m.name, "fog");
  EXPECT_FALSE(m.fillsSpace);
  expectVec3Eq(m.sigmaA, {0.1f, 0.2f, 0.3f});
  expectVec3Eq(m.sigmaS, {1.0f, 2.0f, 3.0f});
  EXPECT_FLOAT_EQ(m.g, 0.3f);
  EXPECT_TRUE(s.hasMedia());
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();  // the extension is known: no "not supported" warning
  // Centre (11, 2, 3), half sizes (0.5, 1, 2).
  EXPECT_EQ(mediumAt(s.media, {11.0f, 2.0f, 3.0f}), 0);
  EXPECT_EQ(mediumAt(s.media, {11.45f, 2.95f, 4.9f}), 0);
  EXPECT_EQ(mediumAt(s.media, {11.55f, 2.0f, 3.0f}), -1);
  EXPECT_EQ(mediumAt(s.media, {11.0f, 3.05f, 3.0f}), -1);
  EXPECT_EQ(mediumAt(s.media, {11.0f, 2.0f, 5.1f}), -1);
  EXPECT_EQ(mediumAt(s.media, {1.0f, 2.0f, 3.0f}), -1);  // where it would be without the parent
  // boxFromWorld is the inverse.
  glm::mat4 identity = m.boxFromWorld * m.worldFromBox;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) EXPECT_NEAR(identity[i][j], i == j ? 1.0f : 0.0f, 1e-6f);
  // Media do not change the bounds: the floor alone spans x in [-5, 5].
  EXPECT_FLOAT_EQ(s.geometryBounds.upper.x, 5.0f);
}

TEST(MediaLoader, RotatedBox) {
  GltfBuilder b = baseScene();
  // 45 degrees about +y, long along its own x: (x, 0, 0) in box space lands on (x, 0, -x) / sqrt 2 in the world.
  const double h = std::sqrt(0.5);
  const double halfAngle = std::numbers::pi / 8.0;
  mediumNode(b, "slab", fog(),
             {{"rotation", {0.0, std::sin(halfAngle), 0.0, std::cos(halfAngle)}}, {"scale", {2, 1, 0.1}}});
  Scene s = loadScene(b.writeGltf("rotated.gltf"));
  ASSERT_EQ(s.media.size(), 1u);
  const float d = static_cast<float>(1.9 * h);
  EXPECT_EQ(mediumAt(s.media, {d, 0.0f, -d}), 0);   // along the box's long axis
  EXPECT_EQ(mediumAt(s.media, {1.9f, 0.0f, 0.0f}), -1);  // along world x it leaves the thin box at once
  EXPECT_EQ(mediumAt(s.media, {0.0f, 0.0f, 0.09f}), 0);  // 0.064 across the thin axis
  EXPECT_EQ(mediumAt(s.media, {0.1f, 0.0f, 0.1f}), -1);  // 0.14 across the thin axis
}

TEST(MediaLoader, GlobalMediumFillsAllSpaceAndGDefaultsToZero) {
  GltfBuilder b = baseScene();
  b.doc["scenes"][0]["extensions"] = {{kExt, fog({0.01, 0.01, 0.01}, {0.02, 0.03, 0.04})}};
  Scene s = loadScene(b.writeGltf("global.gltf"));
  ASSERT_EQ(s.media.size(), 1u);
  EXPECT_TRUE(s.media[0].fillsSpace);
  EXPECT_EQ(s.media[0].name, "scene");
  EXPECT_EQ(s.media[0].g, 0.0f);
  expectVec3Eq(s.media[0].sigmaS, {0.02f, 0.03f, 0.04f});
  EXPECT_EQ(mediumAt(s.media, {1e6f, -3.0f, 2.0f}), 0);
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
}

TEST(MediaLoader, VacuumAndBoxesSideBySideAreAllowed) {
  GltfBuilder b = baseScene();
  mediumNode(b, "left", fog({0, 0, 0}, {0, 0, 0}), {{"translation", {-1, 0, 0}}});
  mediumNode(b, "right", fog(), {{"translation", {1, 0, 0}}});  // shares the face x = 0
  Scene s = loadScene(b.writeGltf("touching.gltf"));
  ASSERT_EQ(s.media.size(), 2u);
  EXPECT_TRUE(s.media[0].isVacuum());
  EXPECT_TRUE(s.hasMedia());
}

// --- errors -----------------------------------------------------------------------------------------------------

struct BadMedium {
  const char* label;
  json medium;       ///< the extension's value on node 2
  const char* path;  ///< glTF path the message must name, after "nodes[2]"
  const char* what;  ///< and a part of the explanation
};

TEST(MediaLoader, EveryBadValueNamesItsGltfPath) {
  json big = 1e39;  // beyond float
  const BadMedium cases[] = {
      {"negative", fog({0.1, 0.1, 0.1}, {1.0, -0.5, 1.0}), ".extensions.VPLAB_participating_media.sigmaS[1]",
       "must lie in [0, 1e+07]"},
      {"string", fog({"a", 0.1, 0.1}), ".extensions.VPLAB_participating_media.sigmaA[0]", "not a number"},
      {"bool", fog({0.1, 0.1, true}), ".extensions.VPLAB_participating_media.sigmaA[2]", "not a number"},
      {"short", fog({0.1, 0.1, 0.1}, {1.0, 2.0}), ".extensions.VPLAB_participating_media.sigmaS", "3 numbers"},
      {"long", fog({0.1, 0.1, 0.1, 0.1}), ".extensions.VPLAB_participating_media.sigmaA", "3 numbers"},
      {"scalar", fog(0.1), ".extensions.VPLAB_participating_media.sigmaA", "3 numbers"},
      {"beyond float", fog({0.1, 0.1, 0.1}, {1.0, 1.0, big}), ".extensions.VPLAB_participating_media.sigmaS[2]",
       "must lie in"},
      {"beyond bound", fog({2e7, 0.1, 0.1}), ".extensions.VPLAB_participating_media.sigmaA[0]", "must lie in"},
      {"missing sigmaA", {{"sigmaS", {1, 1, 1}}}, ".extensions.VPLAB_participating_media.sigmaA", "required"},
      {"missing sigmaS", {{"sigmaA", {1, 1, 1}}}, ".extensions.VPLAB_participating_media.sigmaS", "required"},
      {"g = 1", with(fog(), "g", 1.0), ".extensions.VPLAB_participating_media.g", "(-1, 1)"},
      {"g = -1.5", with(fog(), "g", -1.5), ".extensions.VPLAB_participating_media.g", "(-1, 1)"},
      {"g string", with(fog(), "g", "forward"), ".extensions.VPLAB_participating_media.g",
       "not a number"},
      {"unknown field", with(fog(), "densty", 2.0), ".extensions.VPLAB_participating_media.densty",
       "unknown field 'densty' (known: sigmaA, sigmaS, g, density"},
      {"density number", with(fog(), "density", 2.0), ".extensions.VPLAB_participating_media.density",
       "must be an object {\"uri\""},
      {"number", 3.0, ".extensions.VPLAB_participating_media", "must be an object"},
      {"array", {1, 2, 3}, ".extensions.VPLAB_participating_media", "must be an object"},
  };
  for (const BadMedium& c : cases) {
    SCOPED_TRACE(c.label);
    GltfBuilder b = baseScene();
    ASSERT_EQ(mediumNode(b, "fog", c.medium), 2);
    std::string error = loadError(b.writeGltf("bad.gltf"));
    EXPECT_NE(error.find(std::string("bad.gltf: nodes[2]") + c.path + ":"), std::string::npos) << error;
    EXPECT_NE(error.find(c.what), std::string::npos) << error;
  }
}

TEST(MediaLoader, BadGlobalMediumNamesTheScenesPath) {
  GltfBuilder b = baseScene();
  b.doc["scenes"][0]["extensions"] = {{kExt, fog({0.1, 0.1, 0.1}, {1.0, 1.0, -1.0})}};
  std::string error = loadError(b.writeGltf("bad-global.gltf"));
  EXPECT_NE(error.find("scenes[0].extensions.VPLAB_participating_media.sigmaS[2]:"), std::string::npos) << error;
  b.doc["scenes"][0]["extensions"] = {{kExt, "thick"}};
  error = loadError(b.writeGltf("bad-global.gltf"));
  EXPECT_NE(error.find("scenes[0].extensions.VPLAB_participating_media: must be an object"), std::string::npos)
      << error;
}

TEST(MediaLoader, ExtensionOnAMeshNodeIsAnError) {
  GltfBuilder b = baseScene();
  b.doc["nodes"][0]["extensions"] = {{kExt, fog()}};
  std::string error = loadError(b.writeGltf("mesh.gltf"));
  EXPECT_NE(error.find("nodes[0].extensions.VPLAB_participating_media:"), std::string::npos) << error;
  EXPECT_NE(error.find("node without a mesh"), std::string::npos) << error;
}

TEST(MediaLoader, SingularBoxTransformsAreErrors) {
  const json transforms[] = {
      {{"scale", {1, 0, 1}}},
      {{"scale", {1e-30, 1e-30, 1e-30}}},  // every axis tiny: the inverse overflows float
      // Three axes in the plane z = 0.
      {{"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 0, 0, 1}}},
  };
  for (const json& t : transforms) {
    SCOPED_TRACE(t.dump());
    GltfBuilder b = baseScene();
    mediumNode(b, "flat", fog(), t);
    std::string error = loadError(b.writeGltf("singular.gltf"));
    EXPECT_NE(error.find("singular.gltf: nodes[2].extensions.VPLAB_participating_media: "), std::string::npos)
        << error;
    EXPECT_TRUE(error.find("singular") != std::string::npos || error.find("too small") != std::string::npos)
        << error;
  }
}

TEST(MediaLoader, OverlappingBoxesNameBoth) {
  GltfBuilder b = baseScene();
  mediumNode(b, "mist", fog(), {{"translation", {0, 0, 0}}});
  // Rotated 45 degrees about y and moved so that only its corner reaches into the first box.
  mediumNode(b, "smoke", fog(), {{"translation", {2.3, 0, 0}}, {"rotation", {0, 0.3826834, 0, 0.9238795}}});
  std::string error = loadError(b.writeGltf("overlap.gltf"));
  EXPECT_NE(error.find("nodes[3].extensions.VPLAB_participating_media:"), std::string::npos) << error;
  EXPECT_NE(error.find("nodes[2].extensions.VPLAB_participating_media"), std::string::npos) << error;
  EXPECT_NE(error.find("'smoke'"), std::string::npos) << error;
  EXPECT_NE(error.find("'mist'"), std::string::npos) << error;
  EXPECT_NE(error.find("overlap"), std::string::npos) << error;
}

TEST(MediaLoader, BoxInsideAGlobalMediumNamesBoth) {
  GltfBuilder b = baseScene();
  b.doc["scenes"][0]["extensions"] = {{kExt, fog()}};
  mediumNode(b, "mist", fog(), {{"translation", {100, 0, 0}}});
  std::string error = loadError(b.writeGltf("box-in-global.gltf"));
  EXPECT_NE(error.find("nodes[2].extensions.VPLAB_participating_media:"), std::string::npos) << error;
  EXPECT_NE(error.find("scenes[0].extensions.VPLAB_participating_media"), std::string::npos) << error;
  EXPECT_NE(error.find("'mist'"), std::string::npos) << error;
  EXPECT_NE(error.find("'scene'"), std::string::npos) << error;
}

// --- the bundled fog scenes -------------------------------------------------------------------------------------

TEST(MediaLoader, BundledFogScenesLoadWithTheirMedia) {
  for (const char* name : {"cornell-fog", "fog-shaft"}) {
    SCOPED_TRACE(name);
    EXPECT_LT(std::filesystem::file_size(asset(name)), 100u * 1024u);
    Scene s = loadScene(asset(name));
    EXPECT_TRUE(s.camera.fromFile);
    EXPECT_TRUE(s.hasLights());
    EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
    ASSERT_EQ(s.media.size(), 1u);
    const Medium& m = s.media[0];
    EXPECT_EQ(m.name, "fog");
    EXPECT_FALSE(m.fillsSpace);
    EXPECT_GT(m.g, 0.0f);
    // The fog lies inside the room: every corner within the geometry's bounds.
    for (const glm::vec3& c : m.corners()) {
      EXPECT_TRUE(glm::all(glm::greaterThan(c, s.geometryBounds.lower)));
      EXPECT_TRUE(glm::all(glm::lessThan(c, s.geometryBounds.upper)));
    }
  }
  Scene box = loadScene(asset("cornell-fog"));
  Scene plain = loadScene(asset("cornell-box"));
  EXPECT_EQ(box.triangles.size(), plain.triangles.size());  // the Cornell box itself, unchanged
  const Medium& haze = box.media[0];
  EXPECT_GT(haze.sigmaS.z, haze.sigmaS.x);  // bluish
  float width = 2.0f * glm::length(glm::vec3(haze.worldFromBox[0]));
  EXPECT_NEAR(haze.sigmaT().z * width, box.assetExtras.at("fogOpticalDepthAcrossBlue"), 1e-4);
  EXPECT_GT(haze.sigmaT().x * width, 0.5f);
  EXPECT_LT(haze.sigmaT().z * width, 1.5f);
  EXPECT_EQ(mediumAt(box.media, box.camera.position), -1);  // the official camera stands in front of the box

  Scene shaft = loadScene(asset("fog-shaft"));
  ASSERT_EQ(shaft.punctualLights.size(), 1u);
  EXPECT_EQ(shaft.punctualLights[0].type, PunctualLight::Type::Spot);
  EXPECT_EQ(mediumAt(shaft.media, shaft.punctualLights[0].position), -1);  // outside, shining in
  EXPECT_EQ(mediumAt(shaft.media, shaft.camera.position), 0);              // inside the fog
  float depth = shaft.media[0].sigmaT().x * 2.0f * glm::length(glm::vec3(shaft.media[0].worldFromBox[0]));
  EXPECT_GT(depth, 0.5f);
  EXPECT_LT(depth, 1.0f);
}

TEST(MediaLoader, StagingKeepsTheMedia) {
  for (Stage stage : {Stage::Auto, Stage::Studio}) {
    Scene s = loadScene(asset("fog-shaft"));
    const Medium before = s.media.at(0);
    stageScene(s, stage);
    ASSERT_EQ(s.media.size(), 1u);
    EXPECT_EQ(s.media[0].name, before.name);
    EXPECT_EQ(s.media[0].worldFromBox, before.worldFromBox);
    EXPECT_EQ(s.media[0].sigmaS, before.sigmaS);
  }
}

// --- vplab info -------------------------------------------------------------------------------------------------

std::string runInfo(const std::string& scene) {
  std::string command = std::string(VPLAB_BINARY) + " info " + scene + " 2>&1";
  std::string out;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return out;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, pipe)) out += buffer;
  int status = pclose(pipe);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << out;
  return out;
}

TEST(MediaLoader, InfoListsTheMedia) {
  std::string out = runInfo(asset("cornell-fog"));
  for (const char* part : {"media      1", "media:\n  fog ", "box centre (0.2748, 0.2744, 0.2796), half sizes (",
                           "sigmaA (0.1, 0.1, 0.1), sigmaS (1.2, 1.5, 1.9), sigma_t (1.3, 1.6, 2) 1/m",
                           "albedo (0.9231, 0.9375, 0.95), g 0.3, mean free path (0.7692, 0.625, 0.5) m",
                           "optical depth across the scene", "along the box's longest edge"})
    EXPECT_NE(out.find(part), std::string::npos) << part << "\n" << out;

  GltfBuilder b = baseScene();
  b.doc["scenes"][0]["extensions"] = {{kExt, fog({0, 0, 0}, {0, 0.5, 0})}};
  out = runInfo(b.writeGltf("global.gltf"));
  for (const char* part : {"media:\n  scene ", " all space\n", "mean free path (inf, 2, inf) m"})
    EXPECT_NE(out.find(part), std::string::npos) << part << "\n" << out;
  EXPECT_EQ(out.find("longest edge"), std::string::npos) << out;

  out = runInfo(asset("cornell-box"));
  EXPECT_NE(out.find("media:\n  none\n"), std::string::npos) << out;
}

}  // namespace
}  // namespace vplab
