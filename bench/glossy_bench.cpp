// The glossy comparison table (docs/methods.md "Local virtual lights"): on each glossy scene, the surface methods
// against a converged reference of the indirect light, each given the same time: unbounded VPLs, the bound alone,
// Kollig-Keller compensation, virtual spherical lights and local virtual lights.
//   vplab_bench_glossy_bench [--size N] [--seconds S] [--ref-spp N] [--vpls N] [--bound B] [--lvl-bound B] [--radius R]
//                            [--threads T] [--csv out.csv] [--images DIR] [--ref-cache DIR] [--lvl-sweep]
//                            [scene.gltf ...]
// Default scenes: assets/scenes/cornell-glossy.gltf and glossy-counter.gltf. Each method renders passes of fresh VPL
// sets (one pixel sample each, generation included) until S seconds have passed (renderForSeconds); the row reports
// the time spent, the energy ratio mean(I)/mean(R) of the indirect light, its relMSE and the relMSE of 4x4-pixel block
// averages (which keeps the reference's own noise out). --lvl-bound adds a row of lvl at its own bound (local lights
// can afford a wider residual than Kollig-Keller's per-pixel paths). --lvl-sweep instead renders one pass of lvl per
// tile size and local-light count on the first VPL set and prints their time and 4x4 relMSE (how the defaults were
// chosen).

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "bench/bench_args.h"
#include "bench/comparison_table.h"
#include "evaluation/harness.h"
#include "renderer/core/parallel.h"
#include "renderer/image/heatmap.h"
#include "renderer/image/image_io.h"
#include "renderer/image/metrics.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/offline/path_tracer.h"
#include "renderer/offline/render_methods.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/vpl/vpl_generation.h"

using namespace vplab;

int main(int argc, char** argv) {
  ComparisonOptions o;
  o.size = 256;
  o.refSpp = 1024;
  o.vpls = 1024;
  float bound = 10.0f, radius = 0.03f, lvlBound = 0.0f;
  bool lvlSweep = false;
  for (int i = 1; i < argc; ++i) {
    if (parseComparisonOption(argc, argv, i, o)) continue;
    const std::string a = argv[i];
    if (a == "--bound")
      bound = static_cast<float>(std::atof(benchOptionValue(argc, argv, i).c_str()));
    else if (a == "--lvl-bound")
      lvlBound = static_cast<float>(std::atof(benchOptionValue(argc, argv, i).c_str()));
    else if (a == "--radius")
      radius = static_cast<float>(std::atof(benchOptionValue(argc, argv, i).c_str()));
    else if (a == "--lvl-sweep")
      lvlSweep = true;
    else {
      std::fprintf(stderr, "usage: %s %s [--bound B] [--lvl-bound B] [--radius R] [--lvl-sweep] [scene.gltf ...]\n",
                   argv[0], kComparisonUsage);
      return a == "--help" ? 0 : 2;
    }
  }
  prepareComparison(o, {"cornell-glossy", "glossy-counter"});
  const auto& [scenes, csvPath, imageDir, refDir, size, refSpp, vpls, threads, seconds] = o;

  std::vector<ComparisonRow> rows;
  for (const std::string& path : scenes) {
    const std::string name = std::filesystem::path(path).stem().string();
    OfflineScene offline(loadScene(path));
    const Settings base = comparisonBase(o);

    // The reference of the indirect light, cached per scene and size.
    Settings rs = base;
    rs.samplesPerPixel = refSpp;
    rs.seed = 4242;
    std::fprintf(stderr, "%s: the %d-spp reference (%dx%d)...\n", name.c_str(), refSpp, size, size);
    const Image reference = cachedReference(offline, name, rs, refDir).image;
    const float exposure = autoExposure(reference);
    if (!imageDir.empty()) writeImage(imageDir + "/" + name + "-reference.png", reference, exposure);

    if (lvlSweep) {
      Settings s = base;
      s.clampBound = bound;
      const VplSet set = generateVpls(offline, s);
      const VplRenderResult kk = renderMethod(Method::VplKK).render(offline, set, s, nullptr, {});
      std::printf("%s: vpl-kk b = %g: %.2f s, 4x4 relMSE %.4f\n", name.c_str(), bound, kk.seconds,
                  measureComparison(kk.image, reference).blockRelMse);
      for (int tile : {2, 4, 8, 16})
        for (int lights : {4, 8, 16, 32, 64}) {
          s.lvlTileSize = tile;
          s.lvlLightsPerTile = lights;
          const VplRenderResult r = renderMethod(Method::Lvl).render(offline, set, s, nullptr, {});
          const ComparisonRow m = measureComparison(r.image, reference);
          std::printf("%s: lvl tile %2d, %2d lights: %.2f s, 4x4 relMSE %.4f, energy %.3f\n", name.c_str(), tile,
                      lights, r.seconds, m.blockRelMse, m.energy);
          std::fflush(stdout);
        }
      continue;
    }

    char boundText[32], radiusText[32];
    std::snprintf(boundText, sizeof boundText, "b = %g", bound);
    std::snprintf(radiusText, sizeof radiusText, "r = %g", radius);
    char lvlBoundText[32];
    std::snprintf(lvlBoundText, sizeof lvlBoundText, "b = %g", lvlBound);
    std::vector<ComparisonVariant> variants = {
        {"vpl (unbounded)", Method::Vpl, "b = inf", [](Settings&) {}},
        {"bounding only", Method::Vpl, boundText, [&](Settings& s) { s.clampBound = bound; }},
        {"bias compensation (vpl-kk)", Method::VplKK, boundText, [&](Settings& s) { s.clampBound = bound; }},
        {"virtual spherical lights (vsl)", Method::Vsl, radiusText, [&](Settings& s) { s.vslRadius = radius; }},
        {"local virtual lights (lvl)", Method::Lvl, boundText, [&](Settings& s) { s.clampBound = bound; }},
    };
    if (lvlBound > 0.0f)
      variants.push_back(
          {"local virtual lights (lvl)", Method::Lvl, lvlBoundText, [&](Settings& s) { s.clampBound = lvlBound; }});
    for (const ComparisonVariant& v : variants) {
      Settings s = base;
      v.edit(s);
      const EqualTimeRender r = renderForSeconds(offline, v.method, s, seconds);
      ComparisonRow row = measureComparison(r.image, reference);
      row.scene = name;
      row.method = v.name;
      row.parameters = v.parameters;
      row.seconds = r.seconds;
      row.passes = r.passes;
      row.removed = r.clampEnergyRemoved;
      rows.push_back(row);
      std::fprintf(stderr, "%s: %-32s %6.2f s (%d passes)  4x4 relMSE %.4f  relMSE %.4f  energy %.3f\n", name.c_str(),
                   v.name.c_str(), row.seconds, row.passes, row.blockRelMse, row.relMse, row.energy);
      if (!imageDir.empty()) {
        std::string slug =
            toString(v.method) + std::string(v.method == Method::Vpl && s.clampBound < kInfinity ? "-bounded" : "");
        if (v.method == Method::Lvl && s.clampBound != bound)
          slug += "-b" + std::to_string(static_cast<int>(s.clampBound));
        writeImage(imageDir + "/" + name + "-" + slug + ".png", r.image, exposure);
        HeatmapOptions h;
        h.title = "relative error (I-R)^2/(R^2+0.01)";
        writeHeatmap(imageDir + "/" + name + "-" + slug + "-err.png", relativeErrorImage(r.image, reference), h);
      }
    }
  }
  if (lvlSweep) return 0;

  char title[160];
  std::snprintf(title, sizeof title,
                "glossy comparison at equal time (%.0f s each, %dx%d, %d VPLs per pass, indirect light, %d threads)",
                seconds, size, size, vpls, threads);
  if (!reportComparison(title, rows, csvPath)) return 1;
  return 0;
}
