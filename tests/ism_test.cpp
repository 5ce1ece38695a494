// Imperfect shadow maps, CPU half (renderer/gl/ism.h): the point set is area-proportional and deterministic, each
// caster's run of points is spread like the whole set, and the splatted, hole-filled tiles answer visibility like exact
// ray casting except where their documented failure (thin occluders, gaps) applies. The GL lookup of the same tiles is
// compared with the CPU's exact visibility in gl_accuracy_test.cpp.

#include "renderer/gl/ism.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "renderer/gl/texture_units.h"
#include "tests/test_scenes.h"

namespace vplab {
namespace {

// Two unit quads facing each other at y = 0 (floor, facing +y) and a square occluder at y = 0.5 of half size 0.25.
Scene floorWithOccluder() {
  Scene scene;
  uint32_t white = test::addLambertMaterial(scene, glm::vec3(0.5f));
  test::addQuad(scene, {-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}, white, {0, 1, 0});
  test::addQuad(scene, {-0.25f, 0.5f, -0.25f}, {0.25f, 0.5f, -0.25f}, {0.25f, 0.5f, 0.25f}, {-0.25f, 0.5f, 0.25f},
                white, {0, -1, 0});
  scene.finalize();
  return scene;
}

TEST(Ism, PointsAreAreaProportionalAndDeterministic) {
  Scene scene = floorWithOccluder();
  IsmPoints a = sampleIsmPoints(scene, 20000), b = sampleIsmPoints(scene, 20000);
  ASSERT_EQ(a.size(), 20000u);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_NEAR(a.totalArea, 4.0 + 0.25, 1e-5);
  int onOccluder = 0;
  for (uint32_t t : a.triangles) onOccluder += t >= 2;  // triangles 2 and 3 are the occluder
  // Stratified along the area CDF: the share is exact up to one stratum.
  EXPECT_NEAR(onOccluder / 20000.0, 0.25 / 4.25, 1.0 / 20000.0 + 1e-9);
}

TEST(Ism, EveryCasterRunCoversTheSurface) {
  Scene scene = floorWithOccluder();
  IsmPoints points = sampleIsmPoints(scene, 40000);
  // For any caster count (a VPL set's size changes from one set to the next, the points do not) each caster's run has
  // points in every quarter of the floor, about a quarter of its floor points each.
  for (int casters : {100, 97, 256}) {
    EXPECT_EQ(points.casterRange(casters - 1, casters).second, points.size());
    for (int i = 0; i < casters; ++i) {
      int quarter[4] = {0, 0, 0, 0}, floor = 0;
      const auto [begin, end] = points.casterRange(i, casters);
      for (std::size_t j = begin; j < end; ++j) {
        glm::vec3 p = points.positions[j];
        if (p.y > 0.25f) continue;
        ++floor;
        ++quarter[(p.x > 0) + 2 * (p.z > 0)];
      }
      for (int q : quarter) EXPECT_NEAR(q, floor / 4.0, 0.03 * floor) << "caster " << i << " of " << casters;
    }
  }
}

TEST(Ism, TilesAnswerVisibilityLikeRayCasting) {
  Scene scene = floorWithOccluder();
  IsmPoints points = sampleIsmPoints(scene, 1 << 18);
  // Casters 0.9 m above the floor facing down see the floor; the occluder hides a square of it from each.
  std::vector<VplCaster> casters;
  for (int i = 0; i < 16; ++i)
    casters.push_back({glm::vec3(-0.3f + 0.04f * i, 0.9f, 0.05f * (i % 3)), glm::vec3(0, -1, 0)});
  IsmLayout layout = ismLayout(16, 64, 4096);
  const float far = 6.0f, bias = 0.01f;
  std::vector<uint16_t> tiles = splatIsmTiles(points, casters, layout, far, 3, 2);
  EXPECT_EQ(tiles, splatIsmTiles(points, casters, layout, far, 3, 1)) << "thread count changed the tiles";
  int agree = 0, total = 0;
  for (int c = 0; c < 16; ++c)
    for (int yi = 0; yi < 24; ++yi)
      for (int xi = 0; xi < 24; ++xi) {
        glm::vec3 x(-0.9f + 1.8f * (xi + 0.5f) / 24.0f, 0.0f, -0.9f + 1.8f * (yi + 0.5f) / 24.0f);
        // Exact: the segment from the caster to x crosses the occluder's plane y = 0.5 inside the square.
        glm::vec3 o = casters[c].position;
        float t = (0.5f - o.y) / (x.y - o.y);
        glm::vec3 h = o + t * (x - o);
        bool exact = !(std::abs(h.x) < 0.25f && std::abs(h.z) < 0.25f);
        // Within 1.5 texels of the shadow's edge (measured on the occluder) a tile cannot decide: skipped.
        float margin = 1.5f * (4.0f / 64.0f) * glm::length(h - o);
        float edge = std::max(std::abs(h.x), std::abs(h.z));
        if (std::abs(edge - 0.25f) < margin) continue;
        bool ism = ismVisibility(tiles, layout, c, casters[c], x, glm::vec3(0, 1, 0), far, bias) > 0.5f;
        agree += exact == ism;
        ++total;
      }
  double rate = static_cast<double>(agree) / total;
  std::printf("[ measured ] ISM vs ray casting, 64^2 tiles, 2^18 points / 16 casters: %.4f agree\n", rate);
  EXPECT_GE(rate, 0.99);
}

TEST(Ism, LayoutHoldsEveryTile) {
  IsmLayout l = ismLayout(291, 64, 2048);
  EXPECT_EQ(l.tilesPerRow, 32);
  EXPECT_GE(l.tilesPerLayer * l.layers, 291);
  IsmLayout big = ismLayout(5000, 64, 2048);
  EXPECT_EQ(big.atlasSize(), 2048);
  EXPECT_EQ(big.layers, (5000 + 1023) / 1024);
}

// The texture units and buffer bindings are named once in C++ and once in GLSL; both lists must agree.
TEST(TextureUnits, GlslIncludeMatchesTheEnum) {
  std::ifstream in(std::string(VPLAB_TEST_ASSETS) + "/../shaders/common/units.glsl");
  ASSERT_TRUE(in);
  std::stringstream text;
  text << in.rdbuf();
  std::map<std::string, int> glsl;
  std::regex define(R"(#define ((?:UNIT|BINDING)_[A-Z0-9_]+) (\d+))");
  std::string src = text.str();
  for (std::sregex_iterator it(src.begin(), src.end(), define), end; it != end; ++it)
    glsl[(*it)[1]] = std::stoi((*it)[2]);
  const std::pair<const char*, int> expected[] = {
      {"UNIT_G_POSITION", unit(TextureUnit::GPosition)},
      {"UNIT_G_NORMAL", unit(TextureUnit::GNormal)},
      {"UNIT_G_BASE_COLOR", unit(TextureUnit::GBaseColor)},
      {"UNIT_G_EMISSION", unit(TextureUnit::GEmission)},
      {"UNIT_G_SHADING", unit(TextureUnit::GShading)},
      {"UNIT_SCENE_TEXTURES", unit(TextureUnit::SceneTextures)},
      {"UNIT_PASS_INPUT0", unit(TextureUnit::PassInput0)},
      {"UNIT_PASS_INPUT1", unit(TextureUnit::PassInput1)},
      {"UNIT_PASS_INPUT2", unit(TextureUnit::PassInput2)},
      {"UNIT_PASS_INPUT3", unit(TextureUnit::PassInput3)},
      {"UNIT_G_MERGE_KEY", unit(TextureUnit::GMergeKey)},
      {"UNIT_PASS_INPUT4", unit(TextureUnit::PassInput4)},
      {"UNIT_PASS_INPUT5", unit(TextureUnit::PassInput5)},
      {"UNIT_PASS_INPUT6", unit(TextureUnit::PassInput6)},
      {"UNIT_PASS_INPUT7", unit(TextureUnit::PassInput7)},
      {"UNIT_VISIBILITY", unit(TextureUnit::Visibility)},
      {"UNIT_LIGHT_SHADOWS", unit(TextureUnit::LightShadows)},
      {"UNIT_DIRECTIONAL_SHADOWS", unit(TextureUnit::DirectionalShadows)},
      {"UNIT_BLOCKER_SEARCH", unit(TextureUnit::BlockerSearch)},
      {"UNIT_MEDIA_DENSITY", unit(TextureUnit::MediaDensity)},
      {"UNIT_G_SURFACE", unit(TextureUnit::GSurface)},
      {"BINDING_SCENE_POSITIONS", binding(BufferBinding::ScenePositions)},
      {"BINDING_SCENE_NORMALS", binding(BufferBinding::SceneNormals)},
      {"BINDING_SCENE_UVS", binding(BufferBinding::SceneUvs)},
      {"BINDING_SCENE_TRIANGLES", binding(BufferBinding::SceneTriangles)},
      {"BINDING_SCENE_MATERIALS", binding(BufferBinding::SceneMaterials)},
      {"BINDING_DIRECT_LIGHTS", binding(BufferBinding::DirectLights)},
      {"BINDING_VPLS", binding(BufferBinding::Vpls)},
      {"BINDING_MEDIA", binding(BufferBinding::Media)},
      {"BINDING_MEDIA_DENSITY_GRID", binding(BufferBinding::MediaDensityGrid)},
      {"BINDING_LIGHT_SHADOW_SCALES", binding(BufferBinding::LightShadowScales)},
  };
  EXPECT_EQ(glsl.size(), std::size(expected));
  for (const auto& [name, number] : expected) {
    ASSERT_TRUE(glsl.count(name)) << name;
    EXPECT_EQ(glsl[name], number) << name;
  }
}

// Every binding of the preview's shaders goes by its name, so that a unit is changed in one place.
TEST(TextureUnits, PreviewShadersBindByName) {
  const std::filesystem::path shaders = std::filesystem::path(VPLAB_TEST_ASSETS) / ".." / "shaders";
  std::regex numbered(R"(binding\s*=\s*\d)");
  int files = 0;
  for (const char* dir : {"common", "preview"})
    for (const auto& entry : std::filesystem::directory_iterator(shaders / dir)) {
      if (entry.path().filename() == "units.glsl") continue;
      std::ifstream in(entry.path());
      std::stringstream text;
      text << in.rdbuf();
      const std::string src = text.str();
      EXPECT_FALSE(std::regex_search(src, numbered)) << entry.path() << " binds by number";
      ++files;
    }
  EXPECT_GT(files, 10);
}

}  // namespace
}  // namespace vplab
