// vplab preview <scene>: the GL instant-radiosity preview rendered headless (EGL or OSMesa) from the same VPLs and
// Settings as `vplab render`, with per-pass GPU/CPU timings and the VPL statistics.


#include "app/cli.h"
#include "app/commands.h"
#include "app/comparison.h"
#include "app/file_plan.h"
#include "app/scene_input.h"
#include "app/scene_summary.h"
#include "app/settings_options.h"
#include "app/sweep_options.h"
#include "evaluation/harness.h"
#include "renderer/gl/context.h"
#include "renderer/gl/heap_warmer.h"
#include "renderer/gl/preview_renderer.h"
#include "renderer/image/image_io.h"
#include "renderer/image/metrics.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/offline/representative_lights.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/vpl/vpl_generation.h"

#include <algorithm>
#include <cstdio>
#include <future>
#include <limits>

namespace vplab::app {

int cmdPreview(const Args& args) {
  // k = 4, s = 2 unless told otherwise, as in the editor: the preview is the fast view of the VPLs.
  Settings settings = previewDefaultSettings();
  const unsigned use = kUseImage | kUseGeneration | kUseGl;
  cli::CommandLine cl("vplab preview <scene.gltf|scene.glb> -o image.png|image.exr [options]",
                      cli::imageOutputOptions());
  cl.addOptions({{"ref", "FILE", "reference image: print relMSE, RMSE and energy ratio against it"},
                 {"gl", "auto|egl|osmesa", "headless GL context (default auto: EGL, then OSMesa)"},
                 {"frames", "N", "render N frames and report the last (the first compiles shaders; default 1)"}});
  cl.addOptions(cli::settingOptions(settings, use));
  if (!cl.parse(args)) {
    std::printf("%s", cl.help().c_str());
    std::printf("Generates the VPLs as `vplab render` does (same settings, same seed => same VPLs), then renders the\n"
                "OpenGL 4.5 preview: G-buffer, shadow-mapped direct light, cube shadow maps per VPL, VPL gather\n"
                "(G_b, VSL, k x k interleaving), screen-space bias compensation.\n");
    return 0;
  }
  cl.requirePositional(1, 1, "one scene file");
  GlBackend backend = GlBackend::Auto;
  cli::parseGlOption(cl, backend, false);
  int frames = cl.getInt("frames", 1);
  if (frames < 1 || frames > 10000) throw cli::CliError("option --frames: must be in [1, 10000]");
  cli::applySettingsOptions(cl, settings, use);
  cli::FilePlan files = cli::imageOutputPlan(cl);
  files.check();
  // The first frame's textures land in heap touched on the idle core (heap_warmer.h): about 80 ms less for the
  // Cornell box at 640x480 (docs/benchmarks.md "Warming the heap for the first frame").
  HeapWarmer warmer(previewFirstFrameBytes(settings));
  auto out = cl.value("out");
  auto png = cl.value("png");
  auto refPath = cl.value("ref");
  Image reference;
  if (refPath)
    reference = cli::readReference(*refPath, settings, cli::renderInfo(settings, "gl-preview", 1), "preview");

  // The scene is read on another thread while the context starts: loading the driver (with LLVM) takes tens of
  // milliseconds, as can a large glTF file or a density grid. The GL limits are checked before any VPL is traced. A
  // context that fails waits for the reading to end (the future's destructor), and its error is the one reported.
  std::future<Scene> loading = std::async(std::launch::async, [&] {
    return cli::loadSceneForCommand("preview", cl.positional()[0], settings.stage);
  });
  HeadlessGlContext context(backend);
  Scene scene = loading.get();
  resolveClampBound(settings, scene.geometryBounds.diagonal());
  // Image size, shadow maps and tiles against what this context holds (texture sizes, layers, memory), before the
  // VPLs are traced.
  // Beyond previewRepresentatives VPLs the preview gathers that many representatives (representative_lights.h).
  const int gathered = std::min(settings.vplCount, settings.previewRepresentatives);
  if (std::string problem = previewFitProblem(scene, gathered, settings, queryGlLimits()); !problem.empty())
    throw cli::CliError(problem + " (" + context.description() + ")");
  OfflineScene offline(scene);
  VplSet vpls = generateVpls(offline, settings);
  RepresentativeLights representatives(offline, vpls, settings);
  const VplSet& lights = representatives.select(scene.camera, settings);

  // The renderer comes after the context (which loads the GL function table) and goes before it.
  PreviewRenderer renderer;
  PreviewTimings t;
  PreviewTimings first;
  for (int f = 0; f < frames; ++f) {
    // Later frames redo every screen-space pass, as a camera move would (shadow maps are kept).
    if (f > 0) renderer.invalidateFrame();
    t = renderer.render(scene, lights, settings, scene.camera);
    if (f == 0) first = t;
  }
  Image linear = readPreviewComponents(renderer, settings);
  if (out) writeImage(*out, linear, settings.exposure, cli::renderInfo(settings, "gl-preview", 1));
  if (png) writeImage(*png, linear, settings.exposure);

  const VplStats& st = vpls.stats;
  std::printf("gl          %s\n", context.description().c_str());
  std::printf("scene       %s\n", cli::sceneSummary(scene).c_str());
  const float diagonal = scene.geometryBounds.diagonal();
  std::printf("preview     %dx%d, k = %d, b = %g (%g / diagonal^2), ssbc %d, shadow maps %d, direct samples %d, "
              "seed %u\n",
              settings.width, settings.height, settings.interleave, settings.clampBound,
              settings.clampBound * diagonal * diagonal, settings.ssbcSteps, settings.shadowMapSize,
              settings.directLightSamples, settings.seed);
  // What `auto` picked, and why (resolveVisibility).
  std::string visibility = toString(renderer.visibilityInUse());
  if (settings.visibility == VisibilityMethod::Auto)
    visibility += " (auto: " + std::to_string(scene.triangles.size()) + " triangles x " +
                  std::to_string(lights.vpls.size()) + " VPLs " +
                  (renderer.visibilityInUse() == VisibilityMethod::Cube ? "<=" : ">") + " " VPLAB_AUTO_CUBE_LIMIT ")";
  std::printf("visibility  %s\n", visibility.c_str());
  // Where each density grid went (renderer/gl/density_grid_storage.h): a 3D texture, or a NanoVDB buffer.
  for (const std::string& grid : renderer.densityGridsInUse()) std::printf("density     %s\n", grid.c_str());
  std::printf("vpls        %llu accepted of %llu candidates from %llu light paths (acceptance %.1f%%%s), "
              "generated in %.3f s\n",
              static_cast<unsigned long long>(st.accepted), static_cast<unsigned long long>(st.candidates),
              static_cast<unsigned long long>(st.pathsTraced), 100.0 * st.acceptanceRate,
              st.candidateCapReached ? ", candidate cap reached" : "", st.generationSeconds);
  if (!vpls.vpls.empty()) {
    glm::dvec3 flux(0.0);
    float rMin = std::numeric_limits<float>::max(), rMax = 0.0f;
    uint32_t maxBounce = 0;
    for (const Vpl& v : vpls.vpls) {
      flux += glm::dvec3(v.flux);
      rMin = std::min(rMin, v.radius);
      rMax = std::max(rMax, v.radius);
      maxBounce = std::max(maxBounce, v.bounce);
    }
    std::printf("vpl flux    total (%.4g, %.4g, %.4g), bounces 1..%u, VSL radius %g..%g\n", flux.x, flux.y, flux.z,
                maxBounce, rMin, rMax);
  }
  if (representatives.reduces()) {
    const RepresentativeStats& rs = representatives.stats();
    std::printf(
        "gathered    %zu representatives of the %zu VPLs (a light-tree cut for the view at %zu points: tree "
        "%.1f ms, cut %.1f ms)\n",
        rs.representatives, rs.vpls, rs.points, rs.treeSeconds * 1e3, rs.selectSeconds * 1e3);
  }
  std::printf("frames      %d%s\n", frames,
              frames > 1 ? " (timings of the last; shadow maps from the first)" : " (cold: includes shader compilation)");
  // Shadow maps are rendered once: report them from the first frame.
  struct Row {
    const char* name;
    double gpu, wall;
  };
  const Row rows[] = {{"gbuffer", t.gbufferMs, t.gbufferWallMs},
                      {"light shadows", first.directShadowMs, first.directShadowWallMs},
                      {"direct", t.directMs, t.directWallMs},
                      {"vpl shadows", first.vplShadowMs, first.vplShadowWallMs},
                      {"gather", t.gatherMs, t.gatherWallMs},
                      {"media", t.mediaMs, t.mediaWallMs},
                      {"ssbc", t.ssbcMs, t.ssbcWallMs}};
  std::printf("%-16s %10s %10s\n", "pass", "GPU ms", "wall ms");
  for (const Row& r : rows) std::printf("%-16s %10.2f %10.2f\n", r.name, r.gpu, r.wall);
  double frameGpu = t.gbufferMs + t.directMs + t.gatherMs + t.mediaMs + t.ssbcMs;
  std::printf("%-16s %10.2f %10.2f  (GPU: screen passes; wall: the whole render call)\n", "frame", frameGpu, t.frameWallMs);
  if (t.gatherMs > 0.0)
    std::printf("gather      %.3g pixel x VPL evaluations, %.3f G/s (its de-interleave: %.2f ms)\n",
                t.gatherEvaluations, t.gatherEvaluations / (t.gatherMs * 1e6), t.deinterleaveMs);
  if (refPath) {
    ImageMetrics m = compareImages(linear, reference);
    std::printf("vs ref      relMSE %.6g, RMSE %.6g, energy ratio %.4f (%zu non-finite pixels)\n", m.relMse, m.rmse,
                m.energyRatioOverall, m.nonFinitePixels);
  }
  if (out) std::printf("wrote       %s\n", out->c_str());
  if (png) std::printf("wrote       %s (exposure %+.2f EV)\n", png->c_str(), settings.exposure);
  return 0;
}

}  // namespace vplab::app
