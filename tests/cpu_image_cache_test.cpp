// The GL tests' cache of CPU images (tests/cpu_image_cache.h): what its key covers, and the disk's round trip.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "renderer/core/fnv1a.h"
#include "renderer/vpl/vpl.h"
#include "tests/cpu_image_cache.h"
#include "tests/test_scenes.h"
#include "tests/test_tmp.h"

namespace vplab {
namespace {

// The key's hash (renderer/core/fnv1a.h) is FNV-1a's 64-bit: the published test vectors.
TEST(CpuImageCache, KeysAreFnv1a64) {
  EXPECT_EQ(fnv1a64Hex(""), "cbf29ce484222325");
  EXPECT_EQ(fnv1a64Hex("a"), "af63dc4c8601ec8c");
  EXPECT_EQ(fnv1a64Hex("foobar"), "85944171f73967e8");
}

TEST(CpuImageCache, InputsDifferWhenAnythingARenderReadsDiffers) {
  const Scene scene = test::makePlaneUnderPointLight(1.0f, glm::vec3(0, 0, 1), 2.0f);
  Settings settings;
  VplSet vpls;
  vpls.vpls.resize(3);
  const std::string base = test::renderInputs(scene, settings, &vpls);
  EXPECT_EQ(test::renderInputs(Scene(scene), Settings(settings), &vpls), base);
  EXPECT_NE(test::renderInputs(scene, settings), base) << "without the VPLs";

  Scene moved = scene;
  moved.positions[0].x += 1e-6f;
  EXPECT_NE(test::renderInputs(moved, settings, &vpls), base) << "a vertex";
  Scene rough = scene;
  rough.materials[0].roughness *= 0.5f;
  EXPECT_NE(test::renderInputs(rough, settings, &vpls), base) << "a material";
  Scene dimmer = scene;
  dimmer.punctualLights[0].intensity *= 0.5f;
  EXPECT_NE(test::renderInputs(dimmer, settings, &vpls), base) << "a light";
  Scene turned = scene;
  turned.camera.yfov *= 0.9f;
  EXPECT_NE(test::renderInputs(turned, settings, &vpls), base) << "the camera";
  Settings bounded = settings;
  bounded.clampBound = 20.0f;
  EXPECT_NE(test::renderInputs(scene, bounded, &vpls), base) << "a setting";
  VplSet brighter = vpls;
  brighter.vpls[2].flux.g = 1.0f;
  EXPECT_NE(test::renderInputs(scene, settings, &brighter), base) << "a VPL";
  VplSet withRay = vpls;
  withRay.vrls.resize(1);
  EXPECT_NE(test::renderInputs(scene, settings, &withRay), base) << "a VRL";
}

TEST(CpuImageCache, TheFolderGivesBackTheRenderedImageBitForBit) {
  const std::string folder = test::tmpDir();
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  Image image(3, 2);
  image.at(0, 0) = glm::vec3(1.0f / 3.0f, 1e-30f, 3e38f);
  image.at(2, 1) = glm::vec3(std::nextafter(1.0f, 2.0f), 0.1f, 7.0f);
  int renders = 0;
  auto render = [&] {
    ++renders;
    return image;
  };
  const Image first = test::imageInFolder(folder, "some render | inputs", render);
  const Image second = test::imageInFolder(folder, "some render | inputs", render);
  EXPECT_EQ(renders, 1);
  ASSERT_EQ(second.width, 3);
  ASSERT_EQ(second.height, 2);
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    EXPECT_EQ(first.pixels[i], image.pixels[i]) << i;
    EXPECT_EQ(second.pixels[i], image.pixels[i]) << i;
  }
  // Another key renders its own image.
  test::imageInFolder(folder, "another render | inputs", render);
  EXPECT_EQ(renders, 2);
  // A damaged file is rendered again, not read.
  for (const auto& entry : std::filesystem::directory_iterator(folder))
    if (entry.path().extension() == ".pfm") std::ofstream(entry.path(), std::ios::trunc) << "PF\n3 2\n";
  const Image again = test::imageInFolder(folder, "some render | inputs", render);
  EXPECT_EQ(renders, 3);
  EXPECT_EQ(again.pixels, image.pixels);
}

}  // namespace
}  // namespace vplab
