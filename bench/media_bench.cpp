// The media comparison table (docs/methods.md "Participating media"): on each scene with media, every media method at equal
// time against a converged reference of the indirect light, the course's comparison (bounding only, bias compensation,
// approximate compensation, virtual ray lights, virtual beam lights) measured, with unbounded VPLs beside them.
//   vplab_bench_media_bench [--size N] [--seconds S] [--ref-spp N] [--vpls N] [--threads T] [--csv out.csv]
//                           [--images DIR] [--ref-cache DIR] [--split-sets N] [scene.gltf ...]
// Default scenes: assets/scenes/cornell-fog.gltf, fog-shaft.gltf and cornell-smoke.gltf. Each method renders passes of
// fresh light paths (one pixel sample each; vbl: a thinner beam every pass) until S seconds have passed, VPL generation
// included; the row
// reports the time actually spent, relMSE against the reference, and the energy ratio mean(I)/mean(R) of the indirect
// light (emission and direct light are left out of both images: every method computes them with the same estimator, and
// the emitters' pixels would dominate the mean).
// Before the table, the course's split of a compensated render (Engelhardt et al. 2012 report it on a smoke): over
// --split-sets VPL sets (default 8, 0 = none) at 2 pixel samples, the time and shadow rays of the bounded renders, what
// vpl-abc and vpl-kk add to them, and the share of the removed energy vpl-abc returns of what vpl-kk returns.
// --seconds 0 prints only the split.

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "bench/bench_args.h"
#include "bench/comparison_table.h"
#include "evaluation/harness.h"
#include "renderer/core/parallel.h"
#include "renderer/image/image_io.h"
#include "renderer/image/metrics.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/offline/path_tracer.h"
#include "renderer/offline/render_methods.h"
#include "renderer/offline/vpl_renderer.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/vpl/vpl_generation.h"

using namespace vplab;

namespace {

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double meanOf(const Image& image) {
  double sum = 0.0;
  for (const glm::vec3& p : image.pixels) sum += (p.x + p.y + p.z) / 3.0;
  return image.size() > 0 ? sum / static_cast<double>(image.size()) : 0.0;
}

/// The compensation split over `sets` VPL sets (fresh light paths each): the time and the shadow rays of the bounded
/// renders, what vpl-abc and vpl-kk add to them on the same sets, and the share of the removed energy vpl-abc returns,
/// measured against what vpl-kk (unbiased) returns on the same VPLs: (abc - bounded) / (kk - bounded). The same sets
/// in every render cancel most of the VPL sets' own noise, which is as large as the removed energy on a few sets.
void printCompensationSplit(const std::string& name, const OfflineScene& offline, Settings s, float bound, int sets,
                            double referenceMean) {
  s.clampBound = bound;
  const Method methods[3] = {Method::Vpl, Method::VplAbc, Method::VplKK};
  double seconds[3] = {}, mean[3] = {}, rays[3] = {}, removed = 0.0;
  for (int set = 0; set < sets; ++set) {
    s.seed = 4243 + static_cast<uint32_t>(set);
    const VplSet vpls = generateVpls(offline, s);
    for (int m = 0; m < 3; ++m) {
      const double t = now();
      const VplRenderResult r = renderVpl(offline, vpls, methods[m], s);
      seconds[m] += now() - t;
      mean[m] += meanOf(r.image) / sets;
      rays[m] += static_cast<double>(r.shadowRays);
      if (m == 0) removed += r.clampEnergyRemoved / sets;
    }
  }
  std::printf("\n%s: %d VPL sets of %d VPLs, %d pixel samples each, b = %.3g (the bound removes %.1f %%)\n",
              name.c_str(), sets, s.vplCount, s.samplesPerPixel, bound, 100.0 * removed);
  std::printf("| render | time (s) | added to the bounded render | shadow rays (M) | energy / reference | removed energy "
              "returned, of vpl-kk's |\n|---|---|---|---|---|---|\n");
  std::printf("| bounded (vpl) | %.2f | | %.1f | %.3f | 0 %% |\n", seconds[0], rays[0] * 1e-6, mean[0] / referenceMean);
  for (int m = 1; m < 3; ++m)
    std::printf("| %s | %.2f | %.2f s (%.0f %%) | %.1f | %.3f | %.0f %% |\n", toString(methods[m]), seconds[m],
                seconds[m] - seconds[0], 100.0 * (seconds[m] - seconds[0]) / seconds[0], rays[m] * 1e-6,
                mean[m] / referenceMean, 100.0 * (mean[m] - mean[0]) / (mean[2] - mean[0]));
}

}  // namespace

int main(int argc, char** argv) {
  ComparisonOptions o;
  int splitSets = 8;
  for (int i = 1; i < argc; ++i) {
    if (parseComparisonOption(argc, argv, i, o)) continue;
    if (std::string(argv[i]) == "--split-sets") {
      splitSets = std::atoi(benchOptionValue(argc, argv, i).c_str());
      continue;
    }
    std::fprintf(stderr, "usage: %s %s [--split-sets N] [scene.gltf ...]\n", argv[0], kComparisonUsage);
    return std::string(argv[i]) == "--help" ? 0 : 2;
  }
  prepareComparison(o, {"cornell-fog", "fog-shaft", "cornell-smoke"});
  const auto& [scenes, csvPath, imageDir, refDir, size, refSpp, vpls, threads, seconds] = o;
  if (!refDir.empty()) std::filesystem::create_directories(refDir);

  std::vector<ComparisonRow> rows;
  for (const std::string& path : scenes) {
    const std::string name = std::filesystem::path(path).stem().string();
    OfflineScene offline(loadScene(path));
    const float diagonal = offline.scene().geometryBounds.diagonal();
    const Settings base = comparisonBase(o);

    // The reference of the indirect light, cached per scene and size.
    Image reference;
    const std::string cache =
        refDir.empty() ? "" : refDir + "/" + name + "-" + std::to_string(size) + "-" + std::to_string(refSpp) + ".exr";
    if (!cache.empty() && std::filesystem::exists(cache)) {
      reference = readImage(cache);
    } else {
      Settings rs = base;
      rs.samplesPerPixel = refSpp;
      rs.seed = 4242;
      std::fprintf(stderr, "%s: rendering the %d-spp reference (%dx%d)...\n", name.c_str(), refSpp, size, size);
      reference = renderReference(offline, rs).image;
      if (!cache.empty()) writeImage(cache, reference);
    }
    const float exposure = autoExposure(reference);
    if (!imageDir.empty()) writeImage(imageDir + "/" + name + "-reference.png", reference, exposure);

    // A bound that removes a visible share of the energy: its residual ball has a radius of 5 % of the diagonal.
    const float bound = 1.0f / (0.05f * diagonal * 0.05f * diagonal);
    Settings splitSettings = base;
    splitSettings.samplesPerPixel = 2;
    if (splitSets > 0) printCompensationSplit(name, offline, splitSettings, bound, splitSets, meanOf(reference));
    char boundText[64];
    std::snprintf(boundText, sizeof boundText, "b = %.3g", bound);
    const std::vector<ComparisonVariant> variants = {
        {"vpl (unbounded)", Method::Vpl, "b = inf", [](Settings&) {}},
        {"bounding only", Method::Vpl, boundText, [&](Settings& s) { s.clampBound = bound; }},
        {"bias compensation (vpl-kk)", Method::VplKK, boundText, [&](Settings& s) { s.clampBound = bound; }},
        {"approximate compensation (vpl-abc)", Method::VplAbc, boundText, [&](Settings& s) { s.clampBound = bound; }},
        {"virtual ray lights (vrl)", Method::Vrl, "", [](Settings&) {}},
        {"virtual beam lights (vbl)", Method::Vbl, "",
         [](Settings& s) {
           s.beamPasses = 4096;  // one pixel sample per pass: the time budget ends the passes
           s.samplesPerPixel = 1;
         }},
    };
    for (const ComparisonVariant& v : variants) {
      if (seconds <= 0.0) break;
      Settings s = base;
      v.edit(s);
      // Equal time: passes of fresh light paths (seed + pass) at one pixel sample each, averaged, until the budget
      // is spent, so every method spends its time where its error is (VPL, VRL and beam noise alike); vbl's own
      // passes already work this way, with the beam thinning from pass to pass.
      const double start = now();
      VplRenderResult r;
      if (v.method == Method::Vbl) {
        RenderControl control;
        r = renderMethod(v.method).render(offline, VplSet{}, s, &control, [&](const Image&, int) {
          if (now() - start >= seconds) control.cancel = true;
        });
      } else {
        const EqualTimeRender e = renderForSeconds(offline, v.method, s, seconds);
        r.image = e.image;
        r.samplesPerPixel = e.passes;
        r.clampEnergyRemoved = e.clampEnergyRemoved;
      }
      ComparisonRow row = measureComparison(r.image, reference);
      row.scene = name;
      row.method = v.name;
      row.parameters = v.parameters;
      row.seconds = now() - start;
      row.passes = r.samplesPerPixel;
      row.removed = r.clampEnergyRemoved;
      rows.push_back(row);
      std::fprintf(stderr, "%s: %-36s %6.2f s  relMSE %.4f  energy %.3f\n", name.c_str(), v.name.c_str(), row.seconds,
                   row.relMse, row.energy);
      if (!imageDir.empty()) {
        std::string slug =
            toString(v.method) + std::string(v.method == Method::Vpl && s.clampBound < kInfinity ? "-bounded" : "");
        writeImage(imageDir + "/" + name + "-" + slug + ".png", r.image, exposure);
      }
    }
  }

  char title[160];
  std::snprintf(title, sizeof title,
                "media comparison at equal time (%.0f s each, %dx%d, %d VPLs, indirect light, %d threads)", seconds,
                size, size, vpls, threads);
  if (!rows.empty() && !reportComparison(title, rows, csvPath)) return 1;
  return 0;
}
