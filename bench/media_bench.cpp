// The media comparison table (docs/methods.md "Participating media"): on each fog scene, every media method at equal
// time against a converged reference of the indirect light, the course's comparison (bounding only, bias compensation,
// approximate compensation, virtual ray lights, virtual beam lights) measured, with unbounded VPLs beside them.
//   vplab_bench_media_bench [--size N] [--seconds S] [--ref-spp N] [--vpls N] [--threads T] [--csv out.csv]
//                           [--images DIR] [--ref-cache DIR] [scene.gltf ...]
// Default scenes: assets/scenes/cornell-fog.gltf and fog-shaft.gltf. Each method renders passes of fresh light paths
// (one pixel sample each; vbl: a thinner beam every pass) until S seconds have passed, VPL generation included; the row
// reports the time actually spent, relMSE against the reference, and the energy ratio mean(I)/mean(R) of the indirect
// light (emission and direct light are left out of both images: every method computes them with the same estimator, and
// the emitters' pixels would dominate the mean).

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
#include "renderer/scene/gltf_loader.h"
#include "renderer/vpl/vpl_generation.h"

using namespace vplab;

namespace {

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}


}  // namespace

int main(int argc, char** argv) {
  ComparisonOptions o;
  for (int i = 1; i < argc; ++i) {
    if (parseComparisonOption(argc, argv, i, o)) continue;
    std::fprintf(stderr, "usage: %s %s [scene.gltf ...]\n", argv[0], kComparisonUsage);
    return std::string(argv[i]) == "--help" ? 0 : 2;
  }
  prepareComparison(o, {"cornell-fog", "fog-shaft"});
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
  if (!reportComparison(title, rows, csvPath)) return 1;
  return 0;
}
