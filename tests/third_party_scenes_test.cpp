// Real glTF files that nobody here wrote: Debian's assimp-testmodels (scripts/install-deps.sh installs it) puts
// Khronos samples and deliberately malformed files under /usr/share/assimp/models/glTF2. Every one must either fail
// with a clean one-line SceneError or, staged as `--stage auto` does, give a finite reference and preview; the
// staged lightless models must not be black, and the preview must agree with the reference on them.
//
// Sizes are tiny (32^2, a few samples, few VPLs): the point is every file, not image quality.

#include "renderer/gl/context.h"
#include "renderer/gl/preview_renderer.h"
#include "renderer/image/metrics.h"
#include "renderer/offline/emitter_mask.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/offline/path_tracer.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/staging.h"
#include "renderer/vpl/vpl_generation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace vplab {
namespace {

const std::string kModels = "/usr/share/assimp/models/glTF2";

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/// Every .gltf and .glb under kModels, sorted (directory order is not deterministic).
std::vector<std::string> modelFiles() {
  std::vector<std::string> files;
  std::error_code ec;
  for (auto it = std::filesystem::recursive_directory_iterator(kModels, ec);
       !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec)) {
    std::string p = it->path().string();
    if (it->is_regular_file() && (endsWith(p, ".gltf") || endsWith(p, ".glb"))) files.push_back(p);
  }
  std::sort(files.begin(), files.end());
  return files;
}

/// The staged scene of a file, or nullopt after checking that the loader's error is one clean line naming the file.
std::optional<Scene> loadStaged(const std::string& path) {
  try {
    Scene scene = loadScene(path);
    stageScene(scene, Stage::Auto);
    return scene;
  } catch (const SceneError& e) {
    std::string message = e.what();
    EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_LT(message.size(), 400u) << message;
    return std::nullopt;
  }
}

Settings tinySettings() {
  Settings s;
  s.width = 32;
  s.height = 32;
  s.samplesPerPixel = 2;
  s.maxDepth = 4;
  s.vplCount = 16;
  s.vplMaxBounces = 3;
  s.threads = 2;
  s.shadowMapSize = 16;
  s.lightShadowMapSize = 64;
  s.directLightSamples = 8;
  return s;
}

std::size_t nonFinite(const Image& image) {
  return static_cast<std::size_t>(
      std::count_if(image.pixels.begin(), image.pixels.end(), [](const glm::vec3& p) { return !isFinite(p); }));
}

TEST(ThirdPartyScenes, EveryFileFailsCleanlyOrGivesAFiniteStagedReference) {
  std::vector<std::string> files = modelFiles();
  ASSERT_GE(files.size(), 40u) << "the glTF 2.0 files of assimp-testmodels are missing under " << kModels
                               << " (scripts/install-deps.sh installs the package)";
  int rendered = 0;
  for (const std::string& path : files) {
    SCOPED_TRACE(path);
    std::optional<Scene> scene = loadStaged(path);
    if (!scene) continue;
    EXPECT_TRUE(scene->hasLights());
    OfflineScene offline(*scene);
    ProgressiveResult result = renderReference(offline, tinySettings());
    EXPECT_EQ(result.nonFiniteSamples, 0u);
    EXPECT_EQ(nonFinite(result.image), 0u);
    ++rendered;
  }
  // Most of the files are valid models; the malformed ones are the minority.
  EXPECT_GE(rendered, 25);
}

TEST(GlThirdPartyScenes, EveryLoadableFileGivesAFiniteStagedPreview) {
  std::vector<std::string> files = modelFiles();
  ASSERT_GE(files.size(), 40u) << "assimp-testmodels missing under " << kModels;
  HeadlessGlContext context;
  PreviewRenderer renderer;  // one renderer for every file: the shaders are compiled once
  int previewed = 0;
  for (const std::string& path : files) {
    SCOPED_TRACE(path);
    std::optional<Scene> scene = loadStaged(path);
    if (!scene) continue;
    Settings s = tinySettings();
    OfflineScene offline(*scene);
    VplSet vpls = generateVpls(offline, s);
    // Each file's scene may sit where the last one did: Scene::id tells them apart.
    renderer.render(*scene, vpls, s, scene->camera);
    EXPECT_EQ(renderer.counters().gbuffer, ++previewed) << "the file's own G-buffer";
    EXPECT_EQ(nonFinite(renderer.readLinear()), 0u);
  }
}

/// Staged models that have no lights of their own: the studio must light them, and the preview's mean must agree with
/// the path-traced reference's within `tolerance` (relative) at `vplCount` VPLs.
// The staged model's preview against the reference: its direct light alone (the preview at 4x box-filtered, the
// emitters and their edges left out) within directTolerance, and the whole image within tolerance.
void expectStagedPreviewMatchesReference(const std::string& file, int vplCount, double directTolerance,
                                         double tolerance) {
  std::optional<Scene> scene = loadStaged(kModels + "/" + file);
  ASSERT_TRUE(scene.has_value());
  ASSERT_FALSE(scene->staging.empty());
  Settings s = tinySettings();
  s.lightShadowMapSize = Settings{}.lightShadowMapSize;  // the direct light's accuracy is measured here
  s.samplesPerPixel = 32;
  s.maxDepth = 8;
  s.vplCount = vplCount;
  s.vplMaxBounces = 7;
  s.shadowMapSize = 64;
  s.directLightSamples = 64;
  OfflineScene offline(*scene);
  double reference = meanLuminance(renderReference(offline, s).image);
  EXPECT_GT(reference, 0.1) << "the staged scene is (nearly) black";
  HeadlessGlContext context;
  PreviewRenderer renderer;

  Settings direct = s;
  direct.width = 4 * s.width;
  direct.height = 4 * s.height;
  renderer.render(*scene, VplSet{}, direct, scene->camera);  // no VPLs: Le + direct
  const Image previewDirect = blockAverage(renderer.readLinear(), 4);
  direct = s;
  direct.components = Components::Direct;
  direct.samplesPerPixel = 64;
  const double directRatio =
      meanRatioExcludingEmitters(previewDirect, renderReference(offline, direct).image,
                                 emitterMask(offline.embree(), s.width, s.height));
  std::printf("[ measured ] %s staged: direct light preview / reference %.4f\n", file.c_str(), directRatio);
  EXPECT_NEAR(directRatio, 1.0, directTolerance);

  renderer.render(*scene, generateVpls(offline, s), s, scene->camera);
  double preview = meanLuminance(renderer.readLinear());
  std::printf("[ measured ] %s staged: whole image preview / reference %.4f\n", file.c_str(), preview / reference);
  EXPECT_NEAR(preview / reference, 1.0, tolerance) << "preview " << preview << ", reference " << reference;
}

// Measured: preview / reference 0.9921 (1024 VPLs), direct alone 0.9964.
TEST(GlThirdPartyScenes, StagedBoxTexturedPreviewMatchesReference) {
  expectStagedPreviewMatchesReference("BoxTextured-glTF/BoxTextured.gltf", 1024, 0.03, 0.05);
}

// 110k triangles under the studio's area light, whose soft shadows fall across the cooling fins: the direct light is
// held to 2.5 % (measured 0.9869 at 32^2; 0.895 before the area lights' shadows were tested per sample in cells). The
// indirect light of 64 VPLs (30 % of the image) is a heavy-tailed estimate: the exact CPU render of 256 VPLs gives 0.70
// and 0.89 of the reference's indirect for seeds 1 and 2, so the whole image keeps a loose bound (measured 0.878).
TEST(GlThirdPartyScenes, StagedEnginePreviewMatchesReference) {
  expectStagedPreviewMatchesReference("2CylinderEngine-glTF-Binary/2CylinderEngine.glb", 64, 0.025, 0.2);
}

}  // namespace
}  // namespace vplab
