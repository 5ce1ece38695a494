// vplab reference <scene>: the path-traced reference, written as linear EXR/PFM (and optionally a PNG).

#include "app/cli.h"
#include "app/commands.h"
#include "app/file_plan.h"
#include "app/scene_input.h"
#include "app/scene_summary.h"
#include "app/settings_options.h"
#include "renderer/image/image_io.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/offline/path_tracer.h"
#include "renderer/scene/gltf_loader.h"

#include <chrono>
#include <cstdio>

namespace vplab::app {

int cmdReference(const Args& args) {
  Settings settings;
  const unsigned use = kUseImage | kUseReference;
  cli::CommandLine cl("vplab reference <scene.gltf|scene.glb> -o image.exr [options]", cli::imageOutputOptions());
  cl.addOptions(cli::settingOptions(settings, use));
  if (!cl.parse(args)) {
    std::printf("%s", cl.help().c_str());
    std::printf("Path-traced reference (NEE + MIS, Russian roulette) on all cores; progress on stderr.\n"
                "--components direct is emission seen directly plus one reflection or scattering event (in a scene\n"
                "with participating media, single scattering included); indirect is the rest.\n");
    return 0;
  }
  cl.requirePositional(1, 1, "one scene file");
  cli::applySettingsOptions(cl, settings, use);
  cli::FilePlan files = cli::imageOutputPlan(cl);
  files.check();
  auto out = cl.value("out");
  auto png = cl.value("png");
  // The accumulated mean, the pass's samples and the written copy: three images of 3 floats per pixel.
  cli::requireMemory(3.0 * 12.0 * settings.width * settings.height,
                     "the " + std::to_string(settings.width) + "x" + std::to_string(settings.height) + " reference");

  Scene scene = cli::loadSceneForCommand("reference", cl.positional()[0], settings.stage);
  auto buildStart = std::chrono::steady_clock::now();
  OfflineScene offline(scene);
  double buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - buildStart).count();

  RenderControl control;
  cli::ProgressReporter progress("reference");
  control.onProgress = [&](float f) { progress.update(f); };
  ReferenceStats stats;
  ProgressiveResult result = renderReference(offline, settings, &control, {}, &stats);
  progress.finish();

  ImageInfo info = cli::renderInfo(settings, toString(Method::Reference), result);
  if (out) writeImage(*out, result.image, settings.exposure, info);
  if (png) writeImage(*png, result.image, settings.exposure);

  double raysPerSecond = result.seconds > 0.0 ? static_cast<double>(stats.totalRays()) / result.seconds : 0.0;
  std::printf("scene       %s; BVH + light table %.1f ms\n", cli::sceneSummary(scene).c_str(), 1e3 * buildSeconds);
  std::printf("image       %dx%d, %s, components %s, max depth %d, seed %u\n", settings.width, settings.height,
              cli::describeSamples("reference", result).c_str(), toString(settings.components), settings.maxDepth,
              settings.seed);
  std::printf("time        %.3f s on %d threads\n", result.seconds, resolveThreadCount(settings.threads));
  std::printf("rays        %llu (camera %llu, bounce %llu, shadow %llu): %.2f Mrays/s\n",
              static_cast<unsigned long long>(stats.totalRays()), static_cast<unsigned long long>(stats.cameraRays),
              static_cast<unsigned long long>(stats.bounceRays), static_cast<unsigned long long>(stats.shadowRays),
              raysPerSecond * 1e-6);
  if (out) std::printf("wrote       %s\n", out->c_str());
  if (png) std::printf("wrote       %s (exposure %+.2f EV)\n", png->c_str(), settings.exposure);
  return 0;
}

}  // namespace vplab::app
