// glTF loading: the shipped scene set, hand-built valid files, and one distinct error per kind of bad input.

#include "renderer/core/sampling.h"
#include "renderer/scene/gltf_loader.h"
#include "tests/scene_test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace vplab {
namespace {

using test::loadError;
using test::GltfBuilder;
using test::tmpPath;

std::string asset(const std::string& name) {
  return std::string(VPLAB_TEST_ASSETS) + "/scenes/" + name + ".gltf";
}

void expectVec3Near(const glm::vec3& a, const glm::vec3& b, float tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

/// Every triangle's winding normal lies on the side of its vertex normals, and the normals are unit length.
void expectConsistentNormals(const Scene& s) {
  for (uint32_t t = 0; t < s.triangles.size(); ++t) {
    const glm::uvec3& tri = s.triangles[t];
    glm::vec3 summed = s.normals[tri.x] + s.normals[tri.y] + s.normals[tri.z];
    ASSERT_GT(glm::dot(s.geometricNormal(t), summed), 0.0f) << "triangle " << t;
    ASSERT_NEAR(glm::length(s.normals[tri.x]), 1.0f, 1e-5f);
  }
}

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

bool hasWarning(const Scene& s, const std::string& part) {
  for (const std::string& w : s.warnings)
    if (w.find(part) != std::string::npos) return true;
  return false;
}

glm::vec3 centroid(const Scene& s, uint32_t t) {
  const glm::uvec3& tri = s.triangles[t];
  return (s.positions[tri.x] + s.positions[tri.y] + s.positions[tri.z]) / 3.0f;
}

// --- the shipped scene set --------------------------------------------------------------------------------------

TEST(SceneLoaderAssets, EveryAssetIsSmallHasCameraLightsAndConsistentNormals) {
  for (const char* name : {"cornell-box", "cornell-glossy", "cornell-indirect", "furnace", "two-rooms"}) {
    SCOPED_TRACE(name);
    EXPECT_LT(std::filesystem::file_size(asset(name)), 100u * 1024u);
    Scene s = loadScene(asset(name));
    EXPECT_TRUE(s.camera.fromFile);
    EXPECT_TRUE(s.hasLights());
    EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
    EXPECT_EQ(s.degenerateTrianglesDropped, 0u);
    EXPECT_EQ(s.triangles.size(), s.triangleMaterials.size());
    expectConsistentNormals(s);
  }
}

TEST(SceneLoaderAssets, CornellBoxMatchesTheMeasuredData) {
  Scene s = loadScene(asset("cornell-box"));
  EXPECT_EQ(s.triangles.size(), 32u);
  EXPECT_EQ(s.emissiveTriangles.size(), 2u);
  EXPECT_EQ(s.assetExtras.at("triangles"), 32.0);
  // Bounds in metres: the published box spans 556 x 548.8 x 559.2 mm.
  expectVec3Near(s.bounds.lower, glm::vec3(0.0f), 1e-6f);
  expectVec3Near(s.bounds.upper, glm::vec3(0.556f, 0.5488f, 0.5592f), 1e-6f);
  // The official camera.
  expectVec3Near(s.camera.position, glm::vec3(0.278f, 0.273f, -0.8f), 1e-6f);
  expectVec3Near(s.camera.forward, glm::vec3(0.0f, 0.0f, 1.0f), 1e-6f);
  expectVec3Near(s.camera.up, glm::vec3(0.0f, 1.0f, 0.0f), 1e-6f);
  EXPECT_NEAR(s.camera.yfov, 2.0f * std::atan(12.5f / 35.0f), 1e-5f);

  const glm::vec3 boxCentre(0.278f, 0.2744f, 0.2796f);
  for (uint32_t t = 0; t < s.triangles.size(); ++t) {
    const Material& m = s.materialOf(t);
    glm::vec3 n = s.geometricNormal(t), c = centroid(s, t);
    // Pure Lambert everywhere: the measured data has no specular lobe.
    EXPECT_EQ(m.metallic, 0.0f);
    EXPECT_EQ(m.roughness, 1.0f);
    EXPECT_EQ(m.specular, 0.0f);
    if (m.isEmissive()) {
      expectVec3Near(m.emission, glm::vec3(17.26f, 11.43f, 3.06f), 1e-4f);
      expectVec3Near(n, glm::vec3(0.0f, -1.0f, 0.0f), 1e-6f);
      EXPECT_NEAR(c.y, 0.5483f, 1e-6f);
    } else if (m.name == "red") {
      expectVec3Near(m.baseColor, glm::vec3(0.475f, 0.045f, 0.049f), 1e-6f);
      EXPECT_LT(n.x, -0.99f);  // left wall (x = 0.556) faces into the box
    } else if (m.name == "green") {
      expectVec3Near(m.baseColor, glm::vec3(0.087f, 0.399f, 0.084f), 1e-6f);
      EXPECT_GT(n.x, 0.99f);
    } else {
      expectVec3Near(m.baseColor, glm::vec3(0.738f, 0.736f, 0.737f), 1e-6f);
      // White: walls face the box centre; block faces point away from the nearest wall, i.e. also toward it
      // except block tops, which face up.
      bool blockTop = std::abs(c.y - 0.165f) < 1e-4f || std::abs(c.y - 0.33f) < 1e-4f;
      if (blockTop)
        EXPECT_GT(n.y, 0.99f);
      else if (c.y > 0.001f && c.y < 0.548f && c.z < 0.559f)
        EXPECT_NEAR(n.y, 0.0f, 1e-3f);  // block sides are vertical
      else
        EXPECT_GT(glm::dot(n, boxCentre - c), 0.0f);
    }
  }
  // The total light area is the published 130 x 105 mm.
  float lightArea = 0.0f;
  for (uint32_t t : s.emissiveTriangles) lightArea += s.triangleArea(t);
  EXPECT_NEAR(lightArea, 0.130f * 0.105f, 1e-6f);
}

TEST(SceneLoaderAssets, BlockSidesPointOutward) {
  Scene s = loadScene(asset("cornell-box"));
  // Block side faces: their outward normal must point away from their block's vertical axis.
  const glm::vec2 shortAxis(0.1855f, 0.169f), tallAxis(0.3685f, 0.351f);
  int sides = 0;
  for (uint32_t t = 0; t < s.triangles.size(); ++t) {
    glm::vec3 c = centroid(s, t), n = s.geometricNormal(t);
    if (std::abs(n.y) > 0.5f || c.x < 0.01f || c.x > 0.54f || c.z > 0.55f) continue;
    glm::vec2 axis = c.y < 0.165f && glm::distance(glm::vec2(c.x, c.z), shortAxis) < 0.15f ? shortAxis : tallAxis;
    EXPECT_GT(glm::dot(glm::vec2(n.x, n.z), glm::vec2(c.x, c.z) - axis), 0.0f) << "triangle " << t;
    ++sides;
  }
  EXPECT_EQ(sides, 16);
}

TEST(SceneLoaderAssets, CornellVariants) {
  Scene glossy = loadScene(asset("cornell-glossy"));
  bool floor = false, block = false;
  for (const Material& m : glossy.materials) {
    if (m.name == "glossy-floor") {
      floor = true;
      EXPECT_EQ(m.metallic, 1.0f);
      EXPECT_NEAR(m.roughness, 0.25f, 1e-6f);
    }
    if (m.name == "glossy-block") {
      block = true;
      EXPECT_EQ(m.metallic, 0.0f);
      EXPECT_NEAR(m.roughness, 0.2f, 1e-6f);
      EXPECT_EQ(m.specular, 1.0f);
    }
  }
  EXPECT_TRUE(floor && block);

  Scene indirect = loadScene(asset("cornell-indirect"));
  ASSERT_EQ(indirect.emissiveTriangles.size(), 2u);
  for (uint32_t t : indirect.emissiveTriangles) {
    expectVec3Near(indirect.geometricNormal(t), glm::vec3(0.0f, 1.0f, 0.0f), 1e-6f);
    EXPECT_NEAR(centroid(indirect, t).y, 0.4483f, 1e-6f);
  }
}

TEST(SceneLoaderAssets, FurnaceIsClosedUniformAndFacesInward) {
  Scene s = loadScene(asset("furnace"));
  double albedo = s.assetExtras.at("albedo");
  EXPECT_NEAR(s.assetExtras.at("expectedRadiance"), 1.0 / (1.0 - albedo), 1e-9);
  EXPECT_EQ(s.emissiveTriangles.size(), s.triangles.size());
  float area = 0.0f;
  for (uint32_t t = 0; t < s.triangles.size(); ++t) {
    const Material& m = s.materialOf(t);
    expectVec3Near(m.baseColor, glm::vec3(static_cast<float>(albedo)), 1e-6f);
    expectVec3Near(m.emission, glm::vec3(1.0f), 1e-6f);
    EXPECT_EQ(m.specular, 0.0f);
    EXPECT_GT(glm::dot(s.geometricNormal(t), -centroid(s, t)), 0.0f);
    area += s.triangleArea(t);
  }
  EXPECT_NEAR(area, 24.0f, 1e-4f);  // six 2 x 2 faces: nothing missing, nothing doubled
  glm::vec3 p = s.camera.position;
  EXPECT_TRUE(glm::all(glm::lessThan(glm::abs(p), glm::vec3(1.0f))));
}

TEST(SceneLoaderAssets, TwoRoomsLightInAViewFromB) {
  Scene s = loadScene(asset("two-rooms"));
  float roomAMax = static_cast<float>(s.assetExtras.at("roomAMaxX"));
  float roomBMin = static_cast<float>(s.assetExtras.at("roomBMinX"));
  ASSERT_FALSE(s.emissiveTriangles.empty());
  for (uint32_t t : s.emissiveTriangles) EXPECT_LT(centroid(s, t).x, roomAMax);
  EXPECT_GT(s.camera.position.x, roomBMin);
  EXPECT_LT(s.camera.forward.x, -0.5f);  // toward the door in the shared wall
}

// --- valid hand-built files ----------------------------------------------------------------------------------------

GltfBuilder triangleScene() {
  GltfBuilder b;
  b.addLightQuad();
  return b;
}

TEST(SceneLoaderValid, IndexTypesAndNonIndexedGiveTheSameTriangles) {
  GltfBuilder b = triangleScene();
  std::vector<glm::vec3> quad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  int pos = b.vec3(quad);
  b.meshNode(b.mesh({GltfBuilder::primitive(pos, b.indicesU8({0, 1, 2, 0, 2, 3}))}));
  b.meshNode(b.mesh({GltfBuilder::primitive(pos, b.indicesU32({0, 1, 2, 0, 2, 3}))}));
  b.meshNode(b.mesh({GltfBuilder::primitive(b.vec3({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}))}));
  Scene s = loadScene(b.writeGltf("index-types.gltf"));
  ASSERT_EQ(s.triangles.size(), 2u + 2u + 2u + 1u);
  // Without NORMAL, every triangle gets its own vertices carrying the face normal (+z for these).
  for (uint32_t t = 2; t < s.triangles.size(); ++t) {
    expectVec3Near(s.geometricNormal(t), glm::vec3(0, 0, 1), 1e-6f);
    expectVec3Near(s.normals[s.triangles[t].x], glm::vec3(0, 0, 1), 1e-6f);
  }
  EXPECT_EQ(s.materialOf(6).name, "default");
  expectVec3Near(s.materialOf(6).baseColor, glm::vec3(1.0f), 0.0f);
}

TEST(SceneLoaderValid, GlbLoadsLikeGltf) {
  GltfBuilder b = triangleScene();
  b.meshNode(b.mesh({GltfBuilder::primitive(b.vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}))}));
  test::writeBytes(tmpPath("valid.glb"), b.glbBytes());
  Scene glb = loadScene(tmpPath("valid.glb"));
  Scene gltf = loadScene(b.writeGltf("valid.gltf"));
  ASSERT_EQ(glb.triangles.size(), 3u);
  ASSERT_EQ(glb.positions.size(), gltf.positions.size());
  for (std::size_t i = 0; i < glb.positions.size(); ++i) EXPECT_EQ(glb.positions[i], gltf.positions[i]);
}

TEST(SceneLoaderValid, NestedTransformsWithMatrixAndMirrorScale) {
  GltfBuilder b = triangleScene();
  // A triangle in the local xy plane whose vertex normals say +z; its winding agrees.
  int pos = b.vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  int nrm = b.vec3({{0, 0, 1}, {0, 0, 1}, {0, 0, 1}});
  int mesh = b.mesh({GltfBuilder::primitive(pos, -1, nrm)});
  // root: translate (1, 2, 3), rotate 90 deg about +y; child: matrix = scale 2 then translate (0, 0, 1);
  // grandchild: mirror in x.
  float h = std::sqrt(0.5f);
  int grandchild = b.node({{"mesh", mesh}, {"scale", {-1.0, 1.0, 1.0}}}, false);
  int child = b.node({{"matrix", {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 1, 1}}, {"children", {grandchild}}}, false);
  b.node({{"translation", {1, 2, 3}}, {"rotation", {0, h, 0, h}}, {"children", {child}}});
  Scene s = loadScene(b.writeGltf("nested.gltf"));
  ASSERT_EQ(s.triangles.size(), 3u);
  // Local p -> mirror (-x, y, z) -> scale 2, +z 1 -> rotate about y by 90 deg ((x, y, z) -> (z, y, -x)) -> +(1,2,3).
  auto expected = [](glm::vec3 p) {
    p = glm::vec3(-p.x, p.y, p.z);
    p = 2.0f * p + glm::vec3(0, 0, 1);
    p = glm::vec3(p.z, p.y, -p.x);
    return p + glm::vec3(1, 2, 3);
  };
  const uint32_t t = 2;
  std::vector<glm::vec3> corners = {s.positions[s.triangles[t].x], s.positions[s.triangles[t].y],
                                    s.positions[s.triangles[t].z]};
  for (glm::vec3 local : {glm::vec3(0, 0, 0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0)}) {
    glm::vec3 want = expected(local);
    bool found = false;
    for (const glm::vec3& c : corners) found = found || glm::distance(c, want) < 1e-5f;
    EXPECT_TRUE(found) << want.x << " " << want.y << " " << want.z;
  }
  // The normal +z maps to +z (mirror keeps z), then rotation sends +z to +x; winding was flipped by the mirror
  // and flipped back, so the geometric normal agrees.
  expectVec3Near(s.normals[s.triangles[t].x], glm::vec3(1, 0, 0), 1e-5f);
  expectVec3Near(s.geometricNormal(t), glm::vec3(1, 0, 0), 1e-5f);
}

TEST(SceneLoaderValid, WindingFollowsVertexNormals) {
  GltfBuilder b = triangleScene();
  // Counter-clockwise seen from +z, but the normals say -z: the loader swaps two corners.
  int pos = b.vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  int nrm = b.vec3({{0, 0, -1}, {0, 0, -1}, {0, 0, -1}});
  b.meshNode(b.mesh({GltfBuilder::primitive(pos, -1, nrm)}));
  Scene s = loadScene(b.writeGltf("winding.gltf"));
  expectVec3Near(s.geometricNormal(2), glm::vec3(0, 0, -1), 1e-6f);
}

TEST(SceneLoaderValid, MaterialsLightsAndCamera) {
  GltfBuilder b;
  int material = b.push(
      "materials", {{"name", "shiny"},
                    {"pbrMetallicRoughness",
                     {{"baseColorFactor", {0.5, 0.25, 1.0, 1.0}}, {"metallicFactor", 0.75}, {"roughnessFactor", 0.3}}},
                    {"emissiveFactor", {1.0, 0.5, 0.0}},
                    {"extensions",
                     {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}},
                      {"KHR_materials_specular", {{"specularFactor", 0.4}}}}}});
  b.meshNode(b.mesh({GltfBuilder::primitive(b.vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}), -1, -1, material)}));
  b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"name", "bulb"}, {"type", "point"}, {"color", {1.0, 0.5, 0.25}}, {"intensity", 8.0}},
      {{"name", "spot"},
       {"type", "spot"},
       {"intensity", 2.0},
       {"spot", {{"innerConeAngle", 0.1}, {"outerConeAngle", 0.5}}}}};
  b.node({{"translation", {0, 3, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  // Spot rotated -90 deg about x: local -z becomes world -y (pointing down).
  float h = std::sqrt(0.5f);
  b.node({{"translation", {1, 2, 0}},
          {"rotation", {-h, 0, 0, h}},
          {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  b.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}};
  int camChild = b.node({{"camera", 0}, {"translation", {0, 0, 5}}}, false);
  b.node({{"translation", {1, 0, 0}}, {"children", {camChild}}});
  Scene s = loadScene(b.writeGltf("materials.gltf"));

  const Material& m = s.materials.at(0);
  EXPECT_EQ(m.name, "shiny");
  expectVec3Near(m.baseColor, glm::vec3(0.5f, 0.25f, 1.0f), 1e-6f);
  EXPECT_NEAR(m.metallic, 0.75f, 1e-6f);
  EXPECT_NEAR(m.roughness, 0.3f, 1e-6f);
  EXPECT_NEAR(m.specular, 0.4f, 1e-6f);
  expectVec3Near(m.emission, glm::vec3(4.0f, 2.0f, 0.0f), 1e-6f);

  ASSERT_EQ(s.punctualLights.size(), 2u);
  const PunctualLight& bulb = s.punctualLights[0];
  EXPECT_EQ(bulb.type, PunctualLight::Type::Point);
  expectVec3Near(bulb.position, glm::vec3(0, 3, 0), 1e-6f);
  expectVec3Near(bulb.intensity, glm::vec3(8.0f, 4.0f, 2.0f), 1e-6f);
  const PunctualLight& spot = s.punctualLights[1];
  EXPECT_EQ(spot.type, PunctualLight::Type::Spot);
  expectVec3Near(spot.direction, glm::vec3(0, -1, 0), 1e-5f);
  EXPECT_NEAR(spot.innerConeAngle, 0.1f, 1e-6f);
  EXPECT_NEAR(spot.outerConeAngle, 0.5f, 1e-6f);

  EXPECT_TRUE(s.camera.fromFile);
  expectVec3Near(s.camera.position, glm::vec3(1, 0, 5), 1e-6f);
  expectVec3Near(s.camera.forward, glm::vec3(0, 0, -1), 1e-6f);
  EXPECT_NEAR(s.camera.yfov, 0.5f, 1e-6f);
  EXPECT_TRUE(s.warnings.empty());
}

TEST(SceneLoaderValid, AutomaticCameraFramesTheBounds) {
  GltfBuilder b = triangleScene();
  Scene s = loadScene(b.writeGltf("no-camera.gltf"));
  EXPECT_FALSE(s.camera.fromFile);
  // Every bounds corner lies inside the vertical field of view, in front of the camera.
  for (int i = 0; i < 8; ++i) {
    glm::vec3 corner((i & 1) ? s.bounds.upper.x : s.bounds.lower.x, (i & 2) ? s.bounds.upper.y : s.bounds.lower.y,
                     (i & 4) ? s.bounds.upper.z : s.bounds.lower.z);
    glm::vec3 d = glm::normalize(corner - s.camera.position);
    EXPECT_GT(glm::dot(d, s.camera.forward), std::cos(0.5f * s.camera.yfov));
  }
}

TEST(SceneLoaderValid, DirectionalLightKeepsDirectionAndIrradiance) {
  GltfBuilder b;
  b.meshNode(b.mesh({GltfBuilder::primitive(b.vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}))}));
  b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"name", "sun"}, {"type", "directional"}, {"color", {1.0, 0.5, 0.25}}, {"intensity", 4.0}}};
  // Rotated -90 deg about x (local -z becomes world -y) and translated far away: the translation is irrelevant.
  float h = std::sqrt(0.5f);
  b.node({{"translation", {100, 200, 300}},
          {"rotation", {-h, 0, 0, h}},
          {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  Scene s = loadScene(b.writeGltf("directional.gltf"));
  ASSERT_EQ(s.punctualLights.size(), 1u);
  const PunctualLight& sun = s.punctualLights[0];
  EXPECT_EQ(sun.type, PunctualLight::Type::Directional);
  EXPECT_TRUE(sun.isDirectional());
  expectVec3Near(sun.direction, glm::vec3(0, -1, 0), 1e-5f);
  expectVec3Near(sun.intensity, glm::vec3(4.0f, 2.0f, 1.0f), 1e-6f);
  EXPECT_TRUE(s.hasLights());
  // The light has no position: the bounds are the triangle's alone, and nothing warns.
  expectVec3Near(s.bounds.upper, glm::vec3(1, 1, 0), 1e-6f);
  EXPECT_TRUE(s.warnings.empty());
}

TEST(SceneLoaderValid, AutomaticCameraFramesTheGeometryNotTheLights) {
  GltfBuilder b;
  b.meshNode(b.mesh({GltfBuilder::primitive(b.vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}))}));
  b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 10.0}}};
  b.node({{"translation", {20, 30, 5}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  Scene s = loadScene(b.writeGltf("far-light.gltf"));
  EXPECT_FALSE(s.camera.fromFile);
  expectVec3Near(s.geometryBounds.upper, glm::vec3(1, 1, 0), 1e-6f);
  expectVec3Near(s.bounds.upper, glm::vec3(20, 30, 5), 1e-6f);
  // Framed on the triangle: its centre straight ahead, the triangle filling a good part of the view.
  glm::vec3 toCenter = glm::normalize(s.geometryBounds.center() - s.camera.position);
  EXPECT_GT(glm::dot(toCenter, s.camera.forward), 0.9999f);
  EXPECT_LT(glm::length(s.geometryBounds.center() - s.camera.position), 5.0f);
}

TEST(SceneLoaderValid, TextureIsDecodedFromSrgb) {
  GltfBuilder b = triangleScene();
  test::writeBytes(tmpPath("tex.bmp"), test::bmp(2, 1, {{255, 128, 0}, {0, 0, 255}}));
  b.doc["images"] = {{{"uri", "tex.bmp"}}};
  b.doc["textures"] = {{{"source", 0}}};
  int material = b.push("materials", {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  int pos = b.vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  int uv = b.vec2({{0, 0}, {1, 0}, {0, 1}});
  nlohmann::json prim = GltfBuilder::primitive(pos, -1, -1, material);
  prim["attributes"]["TEXCOORD_0"] = uv;
  b.meshNode(b.mesh({prim}));
  Scene s = loadScene(b.writeGltf("texture.gltf"));
  ASSERT_EQ(s.textures.size(), 1u);
  const Texture& t = s.textures[0];
  ASSERT_EQ(t.width, 2);
  ASSERT_EQ(t.height, 1);
  // sRGB 128/255 decodes to 0.2158 linear.
  expectVec3Near(t.texels[0], glm::vec3(1.0f, 0.21586f, 0.0f), 1e-4f);
  expectVec3Near(t.texels[1], glm::vec3(0.0f, 0.0f, 1.0f), 1e-6f);
  EXPECT_EQ(s.materialOf(2).baseColorTexture, 0);
  EXPECT_EQ(s.uvs[s.triangles[2].y], glm::vec2(1, 0));
}

TEST(SceneLoaderValid, BaseColourTextureTransformIsAppliedToTheCoordinates) {
  GltfBuilder b = triangleScene();
  test::writeBytes(tmpPath("tex.bmp"), test::bmp(2, 1, {{255, 128, 0}, {0, 0, 255}}));
  b.doc["extensionsUsed"] = {"KHR_texture_transform"};
  b.doc["images"] = {{{"uri", "tex.bmp"}}};
  b.doc["textures"] = {{{"source", 0}}};
  nlohmann::json transform = {{"offset", {0.5, 0.25}}, {"rotation", kPi / 2.0}, {"scale", {2.0, 1.0}}};
  int material = b.push(
      "materials",
      {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}, {"extensions", {{"KHR_texture_transform", transform}}}}}}}});
  int pos = b.vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  int uv = b.vec2({{0, 0}, {1, 0}, {0, 1}});
  nlohmann::json prim = GltfBuilder::primitive(pos, -1, -1, material);
  prim["attributes"]["TEXCOORD_0"] = uv;
  b.meshNode(b.mesh({prim}));
  Scene s = loadScene(b.writeGltf("texture-transform.gltf"));
  EXPECT_FALSE(hasWarning(s, "KHR_texture_transform"));
  // uv' = T(offset) R(rotation) S(scale) uv, R counter-clockwise in v-down space (u' = c u + s v, v' = -s u + c v):
  // (0,0) -> (0.5,0.25), (1,0) -> (0.5,-1.75), (0,1) -> (1.5,0.25).
  const glm::uvec3& t = s.triangles[2];
  EXPECT_NEAR(glm::length(s.uvs[t.x] - glm::vec2(0.5f, 0.25f)), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::length(s.uvs[t.y] - glm::vec2(0.5f, -1.75f)), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::length(s.uvs[t.z] - glm::vec2(1.5f, 0.25f)), 0.0f, 1e-6f);
}

// --- problems that are warnings ----------------------------------------------------------------------------------

TEST(SceneLoaderWarnings, MissingTextureImageFallsBackToTheFactor) {
  GltfBuilder b = triangleScene();
  b.doc["images"] = {{{"uri", "no-such-image.png"}}};
  b.doc["textures"] = {{{"source", 0}}};
  int material = b.push(
      "materials",
      {{"pbrMetallicRoughness", {{"baseColorFactor", {0.2, 0.4, 0.6, 1.0}}, {"baseColorTexture", {{"index", 0}}}}}});
  b.meshNode(b.mesh({GltfBuilder::primitive(b.vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}), -1, -1, material)}));
  Scene s = loadScene(b.writeGltf("missing-texture.gltf"));
  EXPECT_TRUE(hasWarning(s, "no-such-image.png")) << (s.warnings.empty() ? "" : s.warnings.front());
  const Material& m = s.materialOf(2);
  EXPECT_EQ(m.baseColorTexture, -1);
  expectVec3Near(m.baseColor, glm::vec3(0.2f, 0.4f, 0.6f), 1e-6f);
}

TEST(SceneLoaderWarnings, LinesAndPointsAreSkipped) {
  GltfBuilder b = triangleScene();
  int pos = b.vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  b.meshNode(b.mesh({GltfBuilder::primitive(pos, -1, -1, -1, 0), GltfBuilder::primitive(pos, -1, -1, -1, 1),
                     GltfBuilder::primitive(pos)}));
  Scene s = loadScene(b.writeGltf("lines-points.gltf"));
  EXPECT_EQ(s.triangles.size(), 3u);
  EXPECT_TRUE(hasWarning(s, "meshes[1].primitives[0]: mode POINTS"));
  EXPECT_TRUE(hasWarning(s, "meshes[1].primitives[1]: mode LINES"));
}

TEST(SceneLoaderWarnings, DegenerateTrianglesAreDroppedAndCounted) {
  GltfBuilder b = triangleScene();
  int pos = b.vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}});
  // One good triangle, one with a repeated index, one with collinear corners.
  b.meshNode(b.mesh({GltfBuilder::primitive(pos, b.indicesU16({0, 1, 2, 0, 1, 1, 0, 1, 3}))}));
  Scene s = loadScene(b.writeGltf("degenerate.gltf"));
  EXPECT_EQ(s.triangles.size(), 3u);
  EXPECT_EQ(s.degenerateTrianglesDropped, 2u);
}

TEST(SceneLoaderWarnings, NoLights) {
  GltfBuilder b;
  b.meshNode(b.mesh({GltfBuilder::primitive(b.vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}))}));
  Scene s = loadScene(b.writeGltf("no-lights.gltf"));
  EXPECT_FALSE(s.hasLights());
  EXPECT_TRUE(hasWarning(s, "no lights: the image will be black"));
}

// --- bad input: one clear SceneError each -------------------------------------------------------------------------

TEST(SceneLoaderErrors, MissingFile) {
  EXPECT_EQ(loadError(tmpPath("does-not-exist.gltf")), tmpPath("does-not-exist.gltf") + ": no such file");
}

TEST(SceneLoaderErrors, NotGltf) {
  test::writeText(tmpPath("not-gltf.gltf"), "this is not JSON, let alone glTF\n");
  EXPECT_NE(loadError(tmpPath("not-gltf.gltf")).find("not-gltf.gltf: not a valid glTF file"), std::string::npos);
  test::writeText(tmpPath("not-glb.glb"), "plain text");
  EXPECT_NE(loadError(tmpPath("not-glb.glb")).find("not a binary glTF file"), std::string::npos);
}

TEST(SceneLoaderErrors, TruncatedGlb) {
  GltfBuilder b = triangleScene();
  std::vector<unsigned char> bytes = b.glbBytes();
  bytes.resize(bytes.size() - 20);
  test::writeBytes(tmpPath("truncated.glb"), bytes);
  std::string e = loadError(tmpPath("truncated.glb"));
  EXPECT_NE(e.find("truncated.glb: truncated .glb"), std::string::npos) << e;
  bytes.resize(10);
  test::writeBytes(tmpPath("truncated-header.glb"), bytes);
  EXPECT_NE(loadError(tmpPath("truncated-header.glb")).find("truncated .glb (10 bytes)"), std::string::npos);
}

TEST(SceneLoaderErrors, ShortAndMissingBuffers) {
  GltfBuilder b = triangleScene();
  b.writeGltf("short-buffer.gltf", "short.bin");
  std::vector<unsigned char> half(b.bin.begin(), b.bin.begin() + static_cast<long>(b.bin.size() / 2));
  test::writeBytes(tmpPath("short.bin"), half);
  std::string e = loadError(tmpPath("short-buffer.gltf"));
  std::string expected = "short-buffer.gltf: buffers[0]: 'short.bin' has " + std::to_string(half.size()) +
                         " bytes, byteLength says " + std::to_string(b.bin.size());
  EXPECT_NE(e.find(expected), std::string::npos) << e;

  e = loadError(b.writeGltf("short-data-uri.gltf", "", 8));
  expected = "short-data-uri.gltf: buffers[0]: data URI holds " + std::to_string(b.bin.size()) +
             " bytes, byteLength says " + std::to_string(b.bin.size() + 8);
  EXPECT_NE(e.find(expected), std::string::npos) << e;

  std::string path = b.writeGltf("missing-buffer.gltf", "missing.bin");
  std::filesystem::remove(tmpPath("missing.bin"));
  e = loadError(path);
  EXPECT_NE(e.find("missing-buffer.gltf: buffers[0].uri: " + tmpPath("missing.bin") + ": no such file"),
            std::string::npos)
      << e;
}

TEST(SceneLoaderErrors, BufferViewBeyondItsBuffer) {
  GltfBuilder b = triangleScene();
  b.doc["bufferViews"][0]["byteLength"] = 4096;
  std::string e = loadError(b.writeGltf("view-range.gltf"));
  EXPECT_NE(e.find("view-range.gltf: bufferViews[0]: bytes [0, 4096) exceed buffers[0]"), std::string::npos) << e;
}

TEST(SceneLoaderErrors, AccessorOutOfRange) {
  GltfBuilder b = triangleScene();
  b.doc["meshes"][0]["primitives"][0]["indices"] = 7;
  std::string e = loadError(b.writeGltf("accessor-index.gltf"));
  EXPECT_EQ(
      e, tmpPath("accessor-index.gltf") + ": meshes[0].primitives[0].indices: accessor 7 out of range (2 accessors)");

  GltfBuilder c = triangleScene();
  c.doc["accessors"][0]["count"] = 100;  // 100 positions do not fit the 48-byte view
  e = loadError(c.writeGltf("accessor-count.gltf"));
  EXPECT_NE(e.find("meshes[0].primitives[0].attributes.POSITION (accessors[0]): 100 elements"), std::string::npos) << e;
}

TEST(SceneLoaderErrors, IndexOutOfRange) {
  GltfBuilder b;
  int pos = b.vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  b.meshNode(b.mesh({GltfBuilder::primitive(pos, b.indicesU16({0, 1, 9}), -1, b.emissiveMaterial())}));
  std::string e = loadError(b.writeGltf("bad-index.gltf"));
  EXPECT_NE(e.find("meshes[0].primitives[0].indices: index 9 at element 2 out of range (3 vertices)"),
            std::string::npos)
      << e;
}

TEST(SceneLoaderErrors, NonFinitePosition) {
  GltfBuilder b = triangleScene();
  float nan = std::nanf("");
  b.meshNode(b.mesh({GltfBuilder::primitive(b.vec3({{0, 0, 0}, {nan, 0, 0}, {0, 1, 0}}))}));
  std::string e = loadError(b.writeGltf("nan.gltf"));
  EXPECT_NE(e.find("meshes[1].primitives[0].attributes.POSITION: element 1 is not finite"), std::string::npos) << e;
  GltfBuilder c = triangleScene();
  c.meshNode(c.mesh({GltfBuilder::primitive(c.vec3({{0, 0, 0}, {1, 0, 0}, {0, INFINITY, 0}}))}));
  e = loadError(c.writeGltf("inf.gltf"));
  EXPECT_NE(e.find("POSITION: element 2 is not finite"), std::string::npos) << e;
}

TEST(SceneLoaderErrors, BrokenReferences) {
  GltfBuilder b = triangleScene();
  b.doc["scenes"][0]["nodes"].push_back(5);
  EXPECT_NE(loadError(b.writeGltf("bad-node.gltf")).find("scenes[0].nodes[1]: node 5 out of range"), std::string::npos);

  GltfBuilder c = triangleScene();
  c.doc["nodes"][0]["children"] = {0};
  EXPECT_NE(loadError(c.writeGltf("cycle.gltf")).find("nodes[0]: reached twice"), std::string::npos);

  GltfBuilder d = triangleScene();
  d.doc["meshes"][0]["primitives"][0]["material"] = 3;
  EXPECT_NE(
      loadError(d.writeGltf("bad-material.gltf")).find("meshes[0].primitives[0].material: material 3 out of range"),
      std::string::npos);
}

// --- extensions and numbers -----------------------------------------------------------------------------------

TEST(SceneLoaderExtensions, UnsupportedUsedExtensionsAreNamedOnce) {
  GltfBuilder b = triangleScene();
  b.doc["extensionsUsed"] = {"KHR_materials_pbrSpecularGlossiness", "KHR_materials_clearcoat",
                             "KHR_materials_emissive_strength", "KHR_texture_transform"};
  Scene s = loadScene(b.writeGltf("used-extensions.gltf"));
  int named = 0;
  for (const std::string& w : s.warnings) named += w.find("KHR_materials_pbrSpecularGlossiness") != std::string::npos;
  EXPECT_EQ(named, 1);
  EXPECT_TRUE(hasWarning(s, "'KHR_materials_clearcoat' is not supported"));
  EXPECT_FALSE(hasWarning(s, "KHR_materials_emissive_strength"));  // implemented
  EXPECT_FALSE(hasWarning(s, "KHR_texture_transform"));            // implemented for the base colour
}

TEST(SceneLoaderExtensions, UnsupportedRequiredExtensionIsAnErrorSayingWhatToDo) {
  GltfBuilder b = triangleScene();
  b.doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  b.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  std::string draco = loadError(b.writeGltf("draco.gltf"));
  EXPECT_NE(draco.find("extensionsRequired[0]: 'KHR_draco_mesh_compression' is not supported; decompress"),
            std::string::npos)
      << draco;
  EXPECT_NE(draco.find("gltf-transform"), std::string::npos) << draco;

  GltfBuilder c = triangleScene();
  c.doc["extensionsRequired"] = {"KHR_technique_webgl"};
  EXPECT_NE(loadError(c.writeGltf("webgl.gltf")).find("'KHR_technique_webgl' is not supported"), std::string::npos);
}

TEST(SceneLoaderErrors, CoordinatesBeyondTheBound) {
  GltfBuilder b = triangleScene();
  b.node({{"translation", {2e18, 0, 0}}, {"mesh", 0}});
  std::string e = loadError(b.writeGltf("far-node.gltf"));
  EXPECT_NE(e.find("attributes.POSITION: element 0 lies beyond +-1e+09 m"), std::string::npos) << e;

  GltfBuilder c = triangleScene();
  c.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}};
  c.node({{"camera", 0}, {"translation", {0, 0, 1.9e18}}});
  e = loadError(c.writeGltf("far-camera.gltf"));
  EXPECT_NE(e.find("camera beyond"), std::string::npos) << e;
}

TEST(SceneLoaderErrors, EmissionAndIntensityThatOverflowFloat) {
  GltfBuilder b;
  int material = b.push("materials", {{"emissiveFactor", {1e300, 1.0, 1.0}}});
  b.meshNode(b.mesh({GltfBuilder::primitive(b.vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}), -1, -1, material)}));
  std::string e = loadError(b.writeGltf("huge-emission.gltf"));
  EXPECT_NE(e.find("materials[0].emissiveFactor: emitted radiance"), std::string::npos) << e;

  GltfBuilder c;
  int strong = c.push("materials", {{"emissiveFactor", {1.0, 1.0, 1.0}},
                                    {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 1e39}}}}}});
  c.meshNode(c.mesh({GltfBuilder::primitive(c.vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}), -1, -1, strong)}));
  e = loadError(c.writeGltf("huge-strength.gltf"));
  EXPECT_NE(e.find("emissiveStrength: is not a number in [0, 1e+15]"), std::string::npos) << e;

  GltfBuilder d = triangleScene();
  d.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 3e38}}};
  d.node({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  e = loadError(d.writeGltf("huge-intensity.gltf"));
  EXPECT_NE(e.find("KHR_lights_punctual.lights[0]: intensity x color must lie in"), std::string::npos) << e;
}

TEST(SceneLoaderErrors, DeeplyNestedJsonIsRejectedBeforeParsing) {
  GltfBuilder b = triangleScene();
  std::string text = readText(b.writeGltf("shallow.gltf"));
  std::size_t asset = text.find("\"asset\":{");
  ASSERT_NE(asset, std::string::npos);
  std::string deep = "\"extras\":" + std::string(20000, '[') + std::string(20000, ']') + ",";
  text.insert(asset + 9, deep);
  std::string path = test::tmpPath("deep.gltf");
  test::writeText(path, text);
  EXPECT_NE(loadError(path).find("JSON nested deeper than 256 levels"), std::string::npos);
}

TEST(SceneLoaderErrors, UriThatIsADirectory) {
  GltfBuilder b = triangleScene();
  std::string path = b.writeGltf("dir-uri.gltf");
  std::string text = readText(path);
  nlohmann::json doc = nlohmann::json::parse(text);
  doc["buffers"][0]["uri"] = ".";
  test::writeText(path, doc.dump());
  std::string e = loadError(path);
  EXPECT_NE(e.find("buffers[0].uri: '.' is a directory"), std::string::npos) << e;
}

}  // namespace
}  // namespace vplab
