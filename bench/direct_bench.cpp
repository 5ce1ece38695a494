// The preview's direct light against the reference's, on every kind of light: the preview (no VPLs) rendered at 4x the
// size and box-filtered down (it point-samples pixel centres), the reference's direct component path-traced
// (--components direct), both compared over the pixels that are not emitters nor their edges (emitterMask). Prints a
// table (mean ratio preview / reference, relMSE, and both at 4x4 blocks) and writes a CSV; --images DIR also writes
// each pair and a signed difference (blue: the preview too dark).
//
// Built-in cases (docs/benchmarks.md "Direct light in the preview"):
//   cornell-box         the bundled box: a 13 x 10.5 cm emitter 0.5 mm under the ceiling, walls at its horizon
//   cornell-large       the same box with a 40 x 40 cm emitter: a large light close to the walls and blocks
//   cornell-spot        the box's emitter replaced by a spot light under the ceiling
//   cornell-sun         the box without its ceiling under a directional light
// and, for each --model FILE (third-party glTF, e.g. /usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/...):
//   <model> point       a point light two bounding radii above it (irradiance pi at its centre), materials as loaded
//   <model> lambert     the same with every material Lambert (no GGX lobe)
//   <model> studio      staged as the commands stage a model without lights (ground, backdrop, studio area light)
//
// usage: vplab_bench_direct_bench [--gl auto|egl|osmesa] [--size N] [--spp S] [--samples K] [--interleave k]
//                                 [--light-shadow-map-size S] [--csv out.csv] [--images DIR] [--only NAME]
//                                 [--model FILE]...
// --interleave k renders the preview with k x k interleaved samples (the editor's default k = 4: each pixel takes
// K / k^2 of the area-light samples and the geometry-aware merge recombines them).

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "bench/bench_args.h"
#include "evaluation/direct_light_cases.h"
#include "renderer/gl/context.h"
#include "renderer/gl/preview_renderer.h"
#include "renderer/image/image_io.h"
#include "renderer/image/metrics.h"
#include "renderer/offline/emitter_mask.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/offline/path_tracer.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/staging.h"

namespace {

using namespace vplab;
using Clock = std::chrono::steady_clock;

struct Case {
  std::string name;
  std::function<Scene()> make;
};

std::vector<Case> builtInCases(const std::string& assets) {
  const std::string box = assets + "/cornell-box.gltf";
  return {{"cornell-box", [box] { return loadScene(box); }},
          {"cornell-large", [box] { return cornellWithLargeEmitter(box, 0.4f); }},
          {"cornell-spot", [box] { return cornellWithSpotLight(box); }},
          {"cornell-sun", [box] { return cornellUnderSun(box); }}};
}

std::vector<Case> modelCases(const std::string& file) {
  const std::string stem = std::filesystem::path(file).stem().string();
  std::vector<Case> cases;
  cases.push_back({stem + " point", [file] {
                     Scene s = loadScene(file);
                     addPointLightAbove(s);
                     return s;
                   }});
  cases.push_back({stem + " lambert", [file] {
                     Scene s = loadScene(file);
                     makeLambert(s);
                     addPointLightAbove(s);
                     return s;
                   }});
  cases.push_back({stem + " studio", [file] {
                     Scene s = loadScene(file);
                     stageScene(s, Stage::Studio);
                     return s;
                   }});
  return cases;
}

}  // namespace

int main(int argc, char** argv) {
  GlBackend backend = GlBackend::Auto;
  int size = 128, spp = 256, samples = 64, interleave = 1, lightMapSize = Settings{}.lightShadowMapSize;
  std::string csvPath = "direct_bench.csv", imagesDir, only;
  std::vector<std::string> models;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--gl") {
      if (!parseGlBackend(benchOptionValue(argc, argv, i), backend)) {
        std::fprintf(stderr, "%s: bad --gl\n", argv[0]);
        return 2;
      }
    } else if (a == "--size") {
      size = std::stoi(benchOptionValue(argc, argv, i));
    } else if (a == "--spp") {
      spp = std::stoi(benchOptionValue(argc, argv, i));
    } else if (a == "--samples") {
      samples = std::stoi(benchOptionValue(argc, argv, i));
    } else if (a == "--interleave") {
      interleave = std::stoi(benchOptionValue(argc, argv, i));
    } else if (a == "--light-shadow-map-size") {
      lightMapSize = std::stoi(benchOptionValue(argc, argv, i));
    } else if (a == "--csv") {
      csvPath = benchOptionValue(argc, argv, i);
    } else if (a == "--images") {
      imagesDir = benchOptionValue(argc, argv, i);
    } else if (a == "--only") {
      only = benchOptionValue(argc, argv, i);
    } else if (a == "--model") {
      models.push_back(benchOptionValue(argc, argv, i));
    } else {
      std::fprintf(stderr,
                   "usage: %s [--gl auto|egl|osmesa] [--size N] [--spp S] [--samples K] [--interleave k] "
                   "[--light-shadow-map-size S] [--csv out.csv] [--images DIR] [--only NAME] [--model FILE]...\n",
                   argv[0]);
      return 2;
    }
  }
  std::vector<Case> cases = builtInCases(VPLAB_ASSET_DIR "/scenes");
  for (const std::string& m : models)
    for (Case& c : modelCases(m)) cases.push_back(std::move(c));
  if (!imagesDir.empty()) std::filesystem::create_directories(imagesDir);

  HeadlessGlContext context(backend);
  std::ofstream csv(csvPath);
  csv << "case,triangles,size,spp,direct_samples,interleave,mean_ratio,relmse,block_mean_ratio,block_relmse,"
         "excluded_pixels,preview_ms,reference_ms\n";
  std::printf("%-26s %9s %10s %9s %11s %9s %10s %10s\n", "case", "triangles", "mean ratio", "relMSE", "4x4 relMSE",
              "excluded", "preview", "reference");
  for (const Case& c : cases) {
    if (!only.empty() && c.name.find(only) == std::string::npos) continue;
    OfflineScene offline(c.make());
    const Scene& scene = offline.scene();
    Settings s;
    s.width = s.height = 4 * size;
    s.threads = 0;
    s.directLightSamples = samples;
    s.interleave = interleave;
    s.lightShadowMapSize = lightMapSize;
    PreviewRenderer renderer;
    renderer.render(scene, VplSet{}, s, scene.camera);  // compiles the shaders and draws the maps
    renderer.invalidateScene();
    auto t0 = Clock::now();
    renderer.render(scene, VplSet{}, s, scene.camera);
    Image preview = blockAverage(renderer.readLinear(PreviewOutput::Final), 4);
    const double previewMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    Settings r = s;
    r.width = r.height = size;
    r.samplesPerPixel = spp;
    r.components = Components::Direct;
    t0 = Clock::now();
    Image reference = renderReference(offline, r).image;
    const double referenceMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    const PixelMask emitters = emitterMask(offline.embree(), size, size);
    const ImageMetrics m = compareImagesExcluding(preview, reference, emitters);
    const ImageMetrics blocks =
        compareImagesExcluding(blockAverage(preview, 4), blockAverage(reference, 4), blockMask(emitters, 4));
    std::printf("%-26s %9zu %10.4f %9.5f %11.5f %9zu %8.0fms %8.0fms\n", c.name.c_str(), scene.triangles.size(),
                m.energyRatioOverall, m.relMse, blocks.relMse, emitters.count(), previewMs, referenceMs);
    std::fflush(stdout);
    csv << '"' << c.name << "\"," << scene.triangles.size() << ',' << size << ',' << spp << ',' << samples << ','
        << interleave << ',' << m.energyRatioOverall << ',' << m.relMse << ',' << blocks.energyRatioOverall << ','
        << blocks.relMse << ',' << emitters.count() << ',' << previewMs << ',' << referenceMs << '\n';
    if (!imagesDir.empty()) {
      std::string base = imagesDir + "/" + c.name;
      for (char& ch : base)
        if (ch == ' ') ch = '-';
      writeImage(base + "-preview.pfm", preview);
      writeImage(base + "-reference.pfm", reference);
      writeImage(base + "-difference.pfm", signedDifferenceImage(preview, reference));
      writeImage(base + "-preview.png", preview);
      writeImage(base + "-reference.png", reference);
    }
  }
  std::printf("wrote %s\n", csvPath.c_str());
  return 0;
}
