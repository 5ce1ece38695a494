// bench and stability load their scenes as every other command does (app/scene_input.h): staged as --stage says,
// with the editor's lights sidecar applied, reported on stderr in the same words. Run through the vplab binary on a
// model without lights, where staging decides whether anything is lit at all.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "evaluation/csv_log.h"
#include "renderer/image/image_io.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/lights_json.h"
#include "tests/scene_test_util.h"

namespace vplab {
namespace {

namespace fs = std::filesystem;

struct CommandRun {
  int status = -1;
  std::string out;  ///< stdout and stderr together
};

CommandRun vplab(const std::string& arguments) {
  const std::string command = std::string(VPLAB_BINARY) + " " + arguments + " 2>&1";
  CommandRun r;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return r;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, pipe)) r.out += buffer;
  const int status = pclose(pipe);
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

/// The text after "vplab <command>: staged " in a command's output (empty when it staged nothing).
std::string stagedLine(const std::string& out, const std::string& command) {
  const std::string marker = "vplab " + command + ": staged ";
  const std::size_t at = out.find(marker);
  if (at == std::string::npos) return "";
  const std::size_t begin = at + marker.size();
  return out.substr(begin, out.find('\n', begin) - begin);
}

/// Runs `vplab <command> <arguments>`, expects it to succeed, and returns what it says it staged.
std::string stagedBy(const std::string& command, const std::string& arguments) {
  CommandRun r = vplab(command + " " + arguments);
  EXPECT_EQ(r.status, 0) << r.out;
  return stagedLine(r.out, command);
}

/// A lightless model: a unit cube standing on nothing, in its own folder (so that its sidecar is its own).
std::string writeLightlessModel(const std::string& folder) {
  fs::remove_all(test::tmpPath(folder));
  fs::create_directories(test::tmpPath(folder));
  test::GltfBuilder b;
  std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const int pos = b.vec3(p);
  const int idx = b.indicesU16(
      {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4, 3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5});
  const int material = b.push("materials", {{"name", "grey"}, {"pbrMetallicRoughness", {{"metallicFactor", 0.0}}}});
  b.meshNode(b.mesh({test::GltfBuilder::primitive(pos, idx, -1, material)}));
  const std::string path = test::tmpPath(folder + "/cube.glb");
  test::writeBytes(path, b.glbBytes());
  return path;
}

double meanOfCachedReference(const std::string& outDir) {
  double sum = 0.0;
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(outDir + "/references")) {
    Image image = readImage(e.path().string());
    for (const glm::vec3& p : image.pixels) sum += p.r + p.g + p.b;
    n += image.size();
  }
  return n ? sum / static_cast<double>(n) : -1.0;
}

const std::string kBench =
    " --quick --size 8x8 --ref-spp 4 --exact-samples-per-pixel 1 --methods vpl --gl off --threads 1";
const std::string kStability =
    " --quick --frames 2 --size 8x8 --vpl-count 8 --ref-spp 4 --methods vpl --gl off --threads 1 --no-images";

TEST(SweepScenes, BenchAndStabilityStageAsTheOtherCommands) {
  const std::string model = writeLightlessModel("sweep-stage");
  const std::string dir = test::tmpPath("sweep-stage");
  const std::string staged = stagedBy("reference", model + " --size 8x8 --samples-per-pixel 2 --out " + dir + "/r.exr");
  ASSERT_FALSE(staged.empty());

  EXPECT_EQ(stagedBy("bench", model + kBench + " --out " + dir + "/bench"), staged);
  EXPECT_GT(meanOfCachedReference(dir + "/bench"), 0.0) << "the staged studio light lights the model";
  EXPECT_EQ(stagedBy("stability", model + kStability + " --out " + dir + "/stability"), staged);
  std::vector<CsvRow> flicker = readCsv(dir + "/stability/flicker.csv");
  ASSERT_FALSE(flicker.empty());
  EXPECT_GT(std::stod(flicker.front().at("mean_reference")), 0.0);

  // --stage none leaves the model unlit, as in the other commands: a warning, and a black reference.
  CommandRun none = vplab("bench " + model + kBench + " --stage none --out " + dir + "/bench-none");
  ASSERT_EQ(none.status, 0) << none.out;
  EXPECT_EQ(stagedLine(none.out, "bench"), "") << none.out;
  EXPECT_NE(none.out.find("no lights"), std::string::npos) << none.out;
  EXPECT_EQ(meanOfCachedReference(dir + "/bench-none"), 0.0);
  CommandRun bad = vplab("stability " + model + kStability + " --stage nowhere --out " + dir + "/stability-bad");
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.out.find("--stage"), std::string::npos) << bad.out;
}

// Re-running bench into the same folder after the staging changed must not keep rows measured on the other scene: the
// rows of a scene whose reference is rendered anew are redone, and the next run with the same scene reuses them.
TEST(SweepScenes, BenchRedoesTheRowsOfAChangedScene) {
  const std::string model = writeLightlessModel("sweep-restage");
  const std::string out = test::tmpPath("sweep-restage") + "/bench";
  CommandRun staged = vplab("bench " + model + kBench + " --out " + out);
  ASSERT_EQ(staged.status, 0) << staged.out;
  const std::size_t rows = readCsv(out + "/bench.csv").size();
  ASSERT_GT(rows, 0u);

  CommandRun unlit = vplab("bench " + model + kBench + " --stage none --out " + out);
  ASSERT_EQ(unlit.status, 0) << unlit.out;
  EXPECT_NE(unlit.out.find("are redone"), std::string::npos) << unlit.out;
  EXPECT_EQ(unlit.out.find("already in bench.csv"), std::string::npos) << unlit.out;
  EXPECT_EQ(readCsv(out + "/bench.csv").size(), rows);

  CommandRun again = vplab("bench " + model + kBench + " --stage none --out " + out);
  ASSERT_EQ(again.status, 0) << again.out;
  EXPECT_EQ(again.out.find("are redone"), std::string::npos) << again.out;
  EXPECT_NE(again.out.find("already in bench.csv"), std::string::npos) << again.out;
  EXPECT_EQ(readCsv(out + "/bench.csv").size(), rows);
}

TEST(SweepScenes, BenchAndStabilityApplyTheLightsSidecar) {
  const std::string model = writeLightlessModel("sweep-sidecar");
  const std::string dir = test::tmpPath("sweep-sidecar");
  Scene lit = loadScene(model);
  PunctualLight light;
  light.name = "saved";
  light.position = glm::vec3(0.5f, 3.0f, 2.0f);
  light.intensity = glm::vec3(20.0f);
  lit.punctualLights.push_back(light);
  saveLightsFile(lightsSidecarPath(model), lit);

  const std::string staged =
      stagedBy("reference", model + " --stage none --size 8x8 --samples-per-pixel 2 --out " + dir + "/r.exr");
  ASSERT_NE(staged.find(lightsSidecarPath(model)), std::string::npos) << staged;
  // A convex model under one light has no indirect light: compare whole images.
  EXPECT_EQ(stagedBy("bench", model + kBench + " --components all --stage none --out " + dir + "/bench"), staged);
  EXPECT_GT(meanOfCachedReference(dir + "/bench"), 0.0) << "the sidecar's light lights the model";
  EXPECT_EQ(stagedBy("stability", model + kStability + " --stage none --out " + dir + "/stability"), staged);
}

}  // namespace
}  // namespace vplab
