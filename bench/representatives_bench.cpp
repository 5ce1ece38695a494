// The preview at 10^5 VPLs (docs/benchmarks.md "The preview at many VPLs"): N VPLs reduced per view to R
// representatives (renderer/offline/representative_lights.h), gathered by the unchanged preview, against the CPU's
// exact sum over all N VPLs (renderVpl, indirect only, emitter excluded, images at the exact sum's unit mean: relMSE
// per pixel and over 4x4 blocks, mean ratio). Beside it, the same preview of R plain VPLs (today's preview at that
// count) against the exact sum of its own VPLs and of the N VPLs, the times of both previews (cold: maps and
// gather; a camera move: the cut again, the maps of the representatives that moved, the screen passes), and the
// reduced set against the CPU's exact sum of the reduced set itself (what the shadow maps alone cost).
//
// usage: vplab_bench_representatives_bench [--scene file.gltf] [--size N] [--vpls N] [--representatives R]
//                                          [--spp S] [--clamp-bound B] [--shadow-map-size S] [--threads T]

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <utility>

#include "bench/bench_args.h"
#include "renderer/gl/context.h"
#include "renderer/gl/preview_renderer.h"
#include "renderer/image/metrics.h"
#include "renderer/offline/emitter_mask.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/offline/representative_lights.h"
#include "renderer/offline/vpl_renderer.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/staging.h"
#include "renderer/vpl/vpl_generation.h"

namespace {

using namespace vplab;

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void printComparison(const char* what, const Image& image, const Image& exact, const PixelMask& emitters) {
  const ImageMetrics m = compareAtUnitMean(image, exact, emitters);
  const ImageMetrics blocks = compareAtUnitMean(blockAverage(image, 4), blockAverage(exact, 4), blockMask(emitters, 4));
  std::printf("%-58s relMSE %.5f  4x4 blocks %.5f  mean ratio %.4f\n", what, m.relMse, blocks.relMse,
              m.energyRatioOverall);
}

/// A preview's indirect light from the scene's camera (a cold frame), then a frame from `moved` with the lights that
/// movedLights() gives, timed with it.
struct PreviewRun {
  Image image;
  PreviewTimings cold, move;
  double moveMs = 0.0;
};

template <typename MovedLights>
PreviewRun runPreview(const Scene& scene, const VplSet& lights, const Settings& s, const Camera& moved,
                      MovedLights&& movedLights) {
  PreviewRun run;
  PreviewRenderer preview;
  run.cold = preview.render(scene, lights, s, scene.camera);
  run.image = preview.readLinear(PreviewOutput::Indirect);
  const auto start = std::chrono::steady_clock::now();
  run.move = preview.render(scene, movedLights(), s, moved);
  run.moveMs = secondsSince(start) * 1e3;
  return run;
}

}  // namespace

int main(int argc, char** argv) {
  std::string scenePath = "assets/scenes/cornell-box.gltf";
  Settings s;
  s.width = s.height = 128;
  s.vplCount = 100000;
  s.previewRepresentatives = 1024;
  s.samplesPerPixel = 2;
  s.clampBound = 10.0f;
  s.shadowMapSize = 256;
  s.components = Components::Indirect;
  // The integer options, each a setting.
  const std::pair<std::string, int Settings::*> intOptions[] = {
      {"--vpls", &Settings::vplCount},
      {"--representatives", &Settings::previewRepresentatives},
      {"--spp", &Settings::samplesPerPixel},
      {"--shadow-map-size", &Settings::shadowMapSize},
      {"--threads", &Settings::threads}};
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto option =
        std::find_if(std::begin(intOptions), std::end(intOptions), [&](const auto& o) { return o.first == arg; });
    if (option != std::end(intOptions)) {
      s.*(option->second) = std::stoi(benchOptionValue(argc, argv, i));
    } else if (arg == "--scene") {
      scenePath = benchOptionValue(argc, argv, i);
    } else if (arg == "--size") {
      s.width = s.height = std::stoi(benchOptionValue(argc, argv, i));
    } else if (arg == "--clamp-bound") {
      s.clampBound = std::stof(benchOptionValue(argc, argv, i));
    } else {
      std::fprintf(stderr, "%s: unknown option %s\n", argv[0], arg.c_str());
      return 2;
    }
  }
  HeadlessGlContext context;
  // A model without lights gets the studio, as the commands stage it (Stage::Auto).
  Scene scene = loadScene(scenePath);
  stageScene(scene, Stage::Auto);
  OfflineScene offline(scene);
  const PixelMask emitters = emitterMask(offline.embree(), s.width, s.height);
  std::printf("%s, %dx%d, b = %g, VPL maps %d, %d CPU samples per pixel, %s\n", scenePath.c_str(), s.width, s.height,
              s.clampBound, s.shadowMapSize, s.samplesPerPixel, context.description().c_str());

  // The N VPLs, their representatives, and the exact sum over all of them.
  const VplSet vpls = generateVpls(offline, s);
  auto start = std::chrono::steady_clock::now();
  RepresentativeLights reps(offline, vpls, s);
  const VplSet reduced = reps.select(scene.camera, s);
  const double reduceSeconds = secondsSince(start);
  start = std::chrono::steady_clock::now();
  const Image exact = renderVpl(offline, vpls, Method::Vpl, s).image;
  const double exactSeconds = secondsSince(start);
  std::printf(
      "%zu VPLs -> %zu representatives at %zu points: tree %.1f ms, cut %.1f ms (%.1f ms in all); exact sum "
      "over the %zu VPLs %.1f s\n",
      vpls.vpls.size(), reduced.vpls.size(), reps.stats().points, reps.stats().treeSeconds * 1e3,
      reps.stats().selectSeconds * 1e3, reduceSeconds * 1e3, vpls.vpls.size(), exactSeconds);

  // The preview of the representatives: cold, then a camera move (the cut again, the moved maps, the screen passes).
  Camera moved = scene.camera;
  moved.position += 0.02f * scene.bounds.diagonal() * glm::normalize(glm::cross(moved.forward, moved.up));
  const PreviewRun reducedRun =
      runPreview(scene, reduced, s, moved, [&]() -> const VplSet& { return reps.select(moved, s); });
  std::printf(
      "preview of %zu representatives: cold %.0f ms (VPL maps %.0f, gather %.0f); camera move %.0f ms (cut "
      "%.1f ms, %zu representatives moved, VPL maps %.0f, gather %.0f)\n",
      reduced.vpls.size(), reducedRun.cold.frameWallMs, reducedRun.cold.vplShadowWallMs, reducedRun.cold.gatherWallMs,
      reducedRun.moveMs, reps.stats().selectSeconds * 1e3, reps.stats().moved, reducedRun.move.vplShadowWallMs,
      reducedRun.move.gatherWallMs);
  const Image& reducedImage = reducedRun.image;

  // Today's preview of R plain VPLs.
  Settings plain = s;
  plain.vplCount = s.previewRepresentatives;
  const VplSet plainVpls = generateVpls(offline, plain);
  const PreviewRun plainRun = runPreview(scene, plainVpls, plain, moved, [&]() -> const VplSet& { return plainVpls; });
  std::printf(
      "preview of %zu plain VPLs: cold %.0f ms (VPL maps %.0f, gather %.0f); camera move %.0f ms (gather %.0f)\n",
      plainVpls.vpls.size(), plainRun.cold.frameWallMs, plainRun.cold.vplShadowWallMs, plainRun.cold.gatherWallMs,
      plainRun.moveMs, plainRun.move.gatherWallMs);
  const Image& plainImage = plainRun.image;

  const Image reducedExact = renderVpl(offline, reduced, Method::Vpl, s).image;
  const Image plainExact = renderVpl(offline, plainVpls, Method::Vpl, s).image;
  std::printf("at the exact sum's unit mean, emitter excluded:\n");
  printComparison("representatives (preview) vs exact sum of all N VPLs", reducedImage, exact, emitters);
  printComparison("representatives (CPU exact) vs exact sum of all N VPLs", reducedExact, exact, emitters);
  printComparison("representatives (preview) vs their own CPU exact sum", reducedImage, reducedExact, emitters);
  printComparison("R plain VPLs (preview) vs exact sum of all N VPLs", plainImage, exact, emitters);
  printComparison("R plain VPLs (preview) vs their own CPU exact sum", plainImage, plainExact, emitters);
  return 0;
}
