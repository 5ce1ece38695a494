// Density grids in glTF files ("density" in VPLAB_participating_media, docs/scenes.md): OpenVDB files written here with
// OpenVDB itself, placed by the grid's own transform and the node's, and one error per kind of bad grid, each naming
// the glTF path and the file.

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetSphere.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "renderer/scene/density_grid.h"
#include "renderer/invalidation.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/lights_json.h"
#include "renderer/scene/media_gltf.h"
#include "renderer/scene/vdb_grid.h"
#include "tests/scene_test_util.h"

namespace vplab {
namespace {

using test::loadError;
using nlohmann::json;
using test::GltfBuilder;

/// A fog-volume float grid over voxels [0, n)^3 (value `value` each, the first one `first`), voxel size 0.1 m, its
/// index origin at (1, 2, 3) m.
openvdb::FloatGrid::Ptr cubeGrid(const char* name, int n, float value, float first) {
  openvdb::initialize();
  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
  auto acc = grid->getAccessor();
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) acc.setValue(openvdb::Coord(x, y, z), x + y + z == 0 ? first : value);
  openvdb::math::Transform::Ptr xf = openvdb::math::Transform::createLinearTransform(0.1);
  xf->postTranslate(openvdb::Vec3d(1.0, 2.0, 3.0));
  grid->setTransform(xf);
  grid->setGridClass(openvdb::GRID_FOG_VOLUME);
  grid->setName(name);
  return grid;
}

std::string writeVdb(const std::string& file, openvdb::GridPtrVec grids) {
  const std::string path = test::tmpPath(file);
  openvdb::io::File(path).write(grids);
  return path;
}

/// A floor and a light, and a mesh-less node (translated by (10, 0, 0), scaled 2) holding a medium with `density`.
std::string sceneWith(const std::string& name, const json& density) {
  GltfBuilder b;
  int pos = b.vec3({{-50, 0, -50}, {50, 0, -50}, {50, 0, 50}, {-50, 0, 50}});
  int idx = b.indicesU16({0, 2, 1, 0, 3, 2});
  b.meshNode(b.mesh({GltfBuilder::primitive(pos, idx)}));
  b.addLightQuad();
  b.doc["extensionsUsed"] = {kMediaExtension};
  json medium = {{"sigmaA", {0.1, 0.1, 0.1}}, {"sigmaS", {1.0, 2.0, 3.0}}, {"density", density}};
  b.doc["nodes"].push_back({{"name", "smoke"}, {"translation", {10.0, 0.0, 0.0}}, {"scale", {2.0, 2.0, 2.0}},
                            {"extensions", {{kMediaExtension, medium}}}});
  b.doc["scenes"][0]["nodes"].push_back(static_cast<int>(b.doc["nodes"].size()) - 1);
  return b.writeGltf(name);
}

void expectError(const std::string& error, std::initializer_list<const char*> parts) {
  for (const char* part : parts) EXPECT_NE(error.find(part), std::string::npos) << part << "\n" << error;
}

TEST(SmokeLoader, GridIsPlacedByItsTransformAndTheNodes) {
  writeVdb("plume.vdb", {cubeGrid("density", 4, 0.5f, 2.0f)});
  const Scene scene = loadScene(sceneWith("smoke.gltf", {{"uri", "plume.vdb"}, {"scale", 3.0}}));
  ASSERT_EQ(scene.media.size(), 1u);
  const Medium& m = scene.media[0];
  ASSERT_TRUE(m.heterogeneous());
  EXPECT_EQ(m.densityUri, "plume.vdb");
  EXPECT_EQ(m.densityGridName, "density");
  EXPECT_EQ(m.density->activeVoxels, 64u);
  EXPECT_FLOAT_EQ(m.density->minValue, 0.5f);
  EXPECT_FLOAT_EQ(m.density->maxValue, 2.0f);
  // Voxel (i, j, k) sits at the grid's (1, 2, 3) + 0.1 (i, j, k) m, then the node scales by 2 and moves by (10, 0, 0).
  auto world = [](glm::vec3 index) { return glm::vec3(10.0f, 0.0f, 0.0f) + 2.0f * (glm::vec3(1, 2, 3) + 0.1f * index); };
  EXPECT_NEAR(m.densityAt(world(glm::vec3(0.0f))), 3.0f * 2.0f, 1e-4f);
  EXPECT_NEAR(m.densityAt(world(glm::vec3(2.0f, 1.0f, 3.0f))), 3.0f * 0.5f, 1e-4f);
  EXPECT_NEAR(m.densityAt(world(glm::vec3(3.5f, 1.0f, 1.0f))), 3.0f * 0.25f, 1e-4f);  // half way to the empty voxel
  EXPECT_EQ(m.densityAt(world(glm::vec3(5.0f, 1.0f, 1.0f))), 0.0f);
  // The box is where the density can be non-zero: voxels -1 to 4 on each axis.
  EXPECT_EQ(mediumAt(scene.media, world(glm::vec3(-0.9f))), 0);
  EXPECT_EQ(mediumAt(scene.media, world(glm::vec3(3.9f))), 0);
  EXPECT_EQ(mediumAt(scene.media, world(glm::vec3(4.1f))), -1);
  EXPECT_EQ(mediumAt(scene.media, world(glm::vec3(-1.1f))), -1);
  EXPECT_NEAR(m.sigmaTMax().z, 3.1f * 3.0f * 2.0f, 1e-4f);
}

TEST(SmokeLoader, BadGridsAreErrorsNamingThePathAndTheFile) {
  const std::string at = "nodes[2].extensions.VPLAB_participating_media.density";
  writeVdb("two.vdb", {cubeGrid("smoke", 2, 1.0f, 1.0f), cubeGrid("temperature", 2, 1.0f, 1.0f)});
  expectError(loadError(sceneWith("missing.gltf", {{"uri", "nowhere.vdb"}})), {at.c_str(), "nowhere.vdb", "no such file"});
  expectError(loadError(sceneWith("named.gltf", {{"uri", "two.vdb"}})),
              {at.c_str(), "two.vdb", "no grid named 'density'", "grids: smoke, temperature"});
  EXPECT_EQ(loadError(sceneWith("picked.gltf", {{"uri", "two.vdb"}, {"grid", "temperature"}})), "(no error)");

  openvdb::Vec3SGrid::Ptr vectors = openvdb::Vec3SGrid::create();
  vectors->tree().setValue(openvdb::Coord(0, 0, 0), openvdb::Vec3s(1.0f));
  vectors->setName("density");
  writeVdb("vec3.vdb", {vectors});
  expectError(loadError(sceneWith("vec3.gltf", {{"uri", "vec3.vdb"}})), {at.c_str(), "vec3s values", "must be float"});

  openvdb::FloatGrid::Ptr sphere = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(1.0f, openvdb::Vec3f(0.0f), 0.25f);
  sphere->setName("density");
  writeVdb("sphere.vdb", {sphere});
  expectError(loadError(sceneWith("sphere.gltf", {{"uri", "sphere.vdb"}})), {at.c_str(), "level set"});

  writeVdb("negative.vdb", {cubeGrid("density", 2, 1.0f, -0.5f)});
  expectError(loadError(sceneWith("negative.gltf", {{"uri", "negative.vdb"}})),
              {at.c_str(), "active voxel (0, 0, 0) holds -0.5"});
  writeVdb("nan.vdb", {cubeGrid("density", 2, 1.0f, std::nanf(""))});
  expectError(loadError(sceneWith("nan.gltf", {{"uri", "nan.vdb"}})), {at.c_str(), "holds nan"});

  openvdb::FloatGrid::Ptr empty = openvdb::FloatGrid::create(0.0f);
  empty->setName("density");
  writeVdb("empty.vdb", {empty});
  expectError(loadError(sceneWith("empty.gltf", {{"uri", "empty.vdb"}})), {at.c_str(), "no active voxels"});

  // Far apart voxels make a bounding box too big to hold densely: refused before anything is allocated.
  openvdb::FloatGrid::Ptr sparse = openvdb::FloatGrid::create(0.0f);
  sparse->tree().setValue(openvdb::Coord(0, 0, 0), 1.0f);
  sparse->tree().setValue(openvdb::Coord(4000, 4000, 4000), 1.0f);
  sparse->setName("density");
  writeVdb("sparse.vdb", {sparse});
  expectError(loadError(sceneWith("sparse.gltf", {{"uri", "sparse.vdb"}})),
              {at.c_str(), "active voxels span 4001 x 4001 x 4001", "MiB stored densely, over the bound"});

  test::writeText(test::tmpPath("text.vdb"), "not a grid");
  expectError(loadError(sceneWith("text.gltf", {{"uri", "text.vdb"}})), {at.c_str(), "not a readable OpenVDB file"});

  writeVdb("ok.vdb", {cubeGrid("density", 2, 1.0f, 1.0f)});
  expectError(loadError(sceneWith("scale.gltf", {{"uri", "ok.vdb"}, {"scale", -1}})), {(at + ".scale").c_str(), "must lie in [0"});
  expectError(loadError(sceneWith("field.gltf", {{"uri", "ok.vdb"}, {"sigma", 1}})), {(at + ".sigma").c_str(), "unknown field"});
  expectError(loadError(sceneWith("nouri.gltf", {{"grid", "density"}})), {(at + ".uri").c_str(), "required"});
  expectError(loadError(sceneWith("abs.gltf", {{"uri", "file:///tmp/ok.vdb"}})), {(at + ".uri").c_str(), "relative path"});
}

TEST(SmokeLoader, SidecarKeepsTheGridAndEditsRegenerateTheVpls) {
  writeVdb("kept.vdb", {cubeGrid("density", 4, 0.5f, 2.0f)});
  const std::string gltf = sceneWith("kept.gltf", {{"uri", "kept.vdb"}});
  Scene edited = loadScene(gltf);
  const std::vector<Medium> before = edited.media;
  edited.media[0].densityScale = 4.0f;
  glm::mat4 moved = edited.media[0].worldFromBox;
  moved[3] += glm::vec4(0.5f, 0.0f, 0.0f, 0.0f);
  edited.media[0].setBox(moved);
  // A scale or placement change regenerates the VPLs; the same media do not.
  EXPECT_TRUE(staleAfterMediumEdit(before, edited.media).vpls);
  EXPECT_FALSE(staleAfterMediumEdit(before, before).vpls);
  saveLightsFile(lightsSidecarPath(gltf), edited);
  Scene reopened = loadScene(gltf);
  ASSERT_TRUE(applyLightsSidecar(reopened));
  std::filesystem::remove(lightsSidecarPath(gltf));
  ASSERT_EQ(reopened.media.size(), 1u);
  const Medium& m = reopened.media[0];
  ASSERT_TRUE(m.heterogeneous());
  EXPECT_EQ(m.densityScale, 4.0f);
  EXPECT_EQ(m.worldFromBox, moved);
  // The density moved with the box: voxel (0, 0, 0) is 0.5 m further along x.
  const glm::vec3 voxel0 = glm::vec3(10.5f, 0.0f, 0.0f) + 2.0f * glm::vec3(1, 2, 3);
  EXPECT_NEAR(m.densityAt(voxel0), 4.0f * 2.0f, 1e-4f);
  EXPECT_NEAR(edited.media[0].densityAt(voxel0), m.densityAt(voxel0), 1e-6f);
}

TEST(SmokeLoader, InfoDescribesTheGrid) {
  const std::string command = std::string(VPLAB_BINARY) + " info " + VPLAB_TEST_ASSETS + "/scenes/cornell-smoke.gltf 2>&1";
  std::string out;
  FILE* pipe = popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, pipe)) out += buffer;
  const int status = pclose(pipe);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << out;
  expectError(out, {"per unit density", "density grid 'density' of cornell-smoke.vdb, scale 1",
                    "active voxels, stored 34 x 50 x 34", "world bounds (", "voxel (0.008, 0.008, 0.008) m",
                    "density ", "largest optical depth through it along x, y, z ("});
}

}  // namespace
}  // namespace vplab
