// vplab render <scene> --method vpl|vpl-kk|vpl-abc|vsl|vrl|vbl|lvl|lightcuts|lightcuts-kk: VPL generation (with
// optional rejection) and the exact VPL render, or the virtual ray / progressive virtual beam light render
// (renderer/offline/vrl_renderer.h), or local virtual lights (renderer/offline/lvl_renderer.h), or the VPL sum through
// lightcuts (renderer/offline/lightcuts_renderer.h).

#include <cctype>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include "app/cli.h"
#include "app/commands.h"
#include "app/comparison.h"
#include "app/file_plan.h"
#include "app/scene_input.h"
#include "app/scene_summary.h"
#include "app/settings_options.h"
#include "renderer/core/atomic_file.h"
#include "renderer/image/image_io.h"
#include "renderer/image/metrics.h"
#include "renderer/offline/lightcuts_renderer.h"
#include "renderer/offline/mrcs_renderer.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/offline/render_methods.h"
#include "renderer/offline/vpl_renderer.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/vpl/generation_methods.h"
#include "renderer/vpl/vpl_generation.h"
#include "renderer/vpl/vpl_json.h"

namespace vplab::app {

int cmdRender(const Args& args) {
  Settings settings;
  const unsigned use = kUseImage | kUseGeneration | kUseCpuVpl;
  const std::string methodNames = renderMethodNames(false);
  cli::CommandLine cl("vplab render <scene.gltf|scene.glb> --method " + methodNames + " -o image.exr [options]",
                      {{"method", methodNames, "many-light method (default vpl)"}});
  cl.addOptions(cli::imageOutputOptions());
  cl.addOptions({{"ref", "FILE", "reference image: print relMSE, RMSE and energy ratio against it"},
                 {"save-vpls", "FILE", "write the VPL set (accepted and rejected) as JSON"}});
  cl.addOptions(cli::settingOptions(settings, use));
  if (!cl.parse(args)) {
    std::printf("%s", cl.help().c_str());
    std::printf(
        "Generates VPLs by --generation (light tracing: --vpl-count is the expected count, with --rejection the\n"
        "expected accepted count; bidirectional: exactly --vpl-count; metropolis: about --vpl-count), then sums\n"
        "them at every pixel sample with exact shadow rays. vrl lights the media with the light paths' media segments\n"
        "(virtual ray lights, --vrl-samples each); vbl averages --beam-passes passes of fresh VPL sets whose segments\n"
        "are beams of shrinking radius (--beam-radius, --beam-shrink).\nMethods:\n");
    for (const RenderMethod& m : renderMethods())
      if (m.id != Method::Reference)
        std::printf("  %-8s %s (%s): %s\n", toString(m.id), m.label, m.citation, m.summary);
    return 0;
  }
  cl.requirePositional(1, 1, "one scene file");
  Method method = Method::Vpl;
  std::string methodName = cl.getString("method", "vpl");
  if (!parseMethod(methodName, method) || method == Method::Reference)
    throw cli::CliError("option --method: '" + methodName + "' is not one of " + methodNames);
  cli::applySettingsOptions(cl, settings, use);
  cli::FilePlan files = cli::imageOutputPlan(cl);
  auto out = cl.value("out");
  auto png = cl.value("png");
  auto refPath = cl.value("ref");
  auto vplPath = cl.value("save-vpls");
  if (vplPath) {
    // A VPL set is JSON: a name without .json is more likely a mistyped image or scene path than a wish. Devices and
    // FIFOs (an existing path that is not a regular file) are taken as they are.
    std::error_code ec;
    const auto status = std::filesystem::status(*vplPath, ec);
    const bool special = !ec && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status);
    std::string ext = std::filesystem::path(*vplPath).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (!special && ext != ".json")
      throw cli::CliError("option --save-vpls: '" + *vplPath + "' is not .json (the VPL set is written as JSON)");
    files.output("--save-vpls", *vplPath, cli::OutputKind::Text);
  }
  files.check();
  cli::requireMemory(3.0 * 12.0 * settings.width * settings.height,
                     "the " + std::to_string(settings.width) + "x" + std::to_string(settings.height) + " render");

  // Read the reference first: a wrong path should fail before minutes of rendering.
  Image reference;
  if (refPath)
    reference = cli::readReference(*refPath, settings, cli::renderInfo(settings, toString(method), 0), "render");

  Scene scene = cli::loadSceneForCommand("render", cl.positional()[0], settings.stage);
  resolveClampBound(settings, scene.geometryBounds.diagonal());
  // What lightcuts refuses, before the VPLs are generated.
  const bool lightcuts = method == Method::Lightcuts || method == Method::LightcutsKK;
  if (lightcuts || method == Method::Mrcs) {
    try {
      requireLightcutsApply(scene, settings, method);
    } catch (const std::invalid_argument& e) {
      throw cli::CliError(std::string("option --method: ") + e.what());
    }
  }
  OfflineScene offline(scene);

  RenderControl genControl;
  cli::ProgressReporter genProgress("vpls");
  genControl.onProgress = [&](float f) { genProgress.update(f); };
  // vbl makes its own VPL sets, one per pass.
  VplSet vpls = renderMethod(method).usesVpls ? generateVpls(offline, settings, &genControl) : VplSet{};
  genProgress.finish();
  if (vplPath) {
    try {
      saveVplSet(*vplPath, vpls);
    } catch (const VplJsonError& e) {
      throw FileWriteError(e.what());  // a write that failed: main()'s exit status for outputs
    }
  }

  RenderControl control;
  cli::ProgressReporter progress("render");
  control.onProgress = [&](float f) { progress.update(f); };
  const Settings renderSettings = offlineRenderSettings(settings, method);
  // Lightcuts are called directly for their cut statistics.
  LightcutsRenderResult cutResult;
  MrcsRenderResult mrcsResult;
  VplRenderResult result;
  if (lightcuts) {
    cutResult = renderLightcuts(offline, vpls, method, renderSettings, &control, {});
    result = cutResult;
  } else if (method == Method::Mrcs) {
    mrcsResult = renderMrcs(offline, vpls, renderSettings, &control, {});
    result = mrcsResult;
  } else {
    result = renderMethod(method).render(offline, vpls, renderSettings, &control, {});
  }
  progress.finish();

  if (out) writeImage(*out, result.image, settings.exposure, cli::renderInfo(settings, toString(method), result));
  if (png) writeImage(*png, result.image, settings.exposure);

  const VplStats& st = vpls.stats;
  std::printf("scene       %s\n", cli::sceneSummary(scene).c_str());
  std::printf("method      %s, %dx%d, %s, components %s, seed %u\n", toString(method), settings.width, settings.height,
              cli::describeSamples("render", result).c_str(), toString(settings.components), settings.seed);
  std::printf("vpls        %s\n", describeVplStats(st).c_str());
  for (const std::string& w : st.warnings) std::fprintf(stderr, "vplab render: warning: %s\n", w.c_str());
  std::printf("clamp       b = %g (%g / diagonal^2), energy removed %.2f%%\n", settings.clampBound,
              settings.clampBound * scene.geometryBounds.diagonal() * scene.geometryBounds.diagonal(),
              100.0 * result.clampEnergyRemoved);
  std::printf("time        %.3f s on %d threads (%llu VPL shadow rays, %.2f Mrays/s)\n", result.seconds,
              resolveThreadCount(settings.threads), static_cast<unsigned long long>(result.shadowRays),
              result.seconds > 0.0 ? 1e-6 * static_cast<double>(result.shadowRays) / result.seconds : 0.0);
  if (lightcuts)
    std::printf(
        "lightcuts   tree %zu nodes (%.1f MB, %zu B per node) built in %.1f ms; mean cut %.1f nodes, %.1f shadow "
        "rays; %llu of %llu cuts stopped at --lightcut-max %d\n",
        cutResult.treeNodes, 1e-6 * static_cast<double>(cutResult.treeBytes), sizeof(LightTreeNode),
        1e3 * cutResult.treeSeconds, cutResult.meanCut, cutResult.meanShadowRays,
        static_cast<unsigned long long>(cutResult.cutsAtMax), static_cast<unsigned long long>(cutResult.cuts),
        settings.lightcutMax);
  if (method == Method::Mrcs)
    std::printf("mrcs        %zu rows (%zu hit a surface) in %.1f ms, %zu clusters in %.1f ms, %zu VPLs light no row\n",
                static_cast<std::size_t>(settings.mrcsRows), mrcsResult.reduction.rows,
                1e3 * mrcsResult.reduction.rowSeconds, mrcsResult.reduction.reduced.vpls.size(),
                1e3 * mrcsResult.reduction.clusterSeconds, mrcsResult.reduction.darkColumns);
  if (refPath) {
    ImageMetrics m = compareImages(result.image, reference);
    std::printf("vs ref      relMSE %.6g, RMSE %.6g, energy ratio %.4f (%zu non-finite pixels)\n", m.relMse, m.rmse,
                m.energyRatioOverall, m.nonFinitePixels);
  }
  if (vplPath) std::printf("wrote       %s\n", vplPath->c_str());
  if (out) std::printf("wrote       %s\n", out->c_str());
  if (png) std::printf("wrote       %s (exposure %+.2f EV)\n", png->c_str(), settings.exposure);
  return 0;
}

}  // namespace vplab::app
