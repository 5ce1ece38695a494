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

struct Row {
  std::string scene, method, parameters;
  double seconds = 0.0, relMse = 0.0, energy = 0.0, removed = 0.0;
  int samples = 0;
};

/// One table row: the method's settings differ from the base by `edit`.
struct Variant {
  std::string name;  ///< the table's row name
  Method method;
  std::string parameters;
  std::function<void(Settings&)> edit;
};

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> scenes;
  std::string csvPath, imageDir, refDir;
  int size = 128, refSpp = 4096, vpls = 256, threads = 0;
  double seconds = 10.0;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto next = [&] { return benchOptionValue(argc, argv, i); };
    if (a == "--size")
      size = std::atoi(next().c_str());
    else if (a == "--seconds")
      seconds = std::atof(next().c_str());
    else if (a == "--ref-spp")
      refSpp = std::atoi(next().c_str());
    else if (a == "--vpls")
      vpls = std::atoi(next().c_str());
    else if (a == "--threads")
      threads = std::atoi(next().c_str());
    else if (a == "--csv")
      csvPath = next();
    else if (a == "--images")
      imageDir = next();
    else if (a == "--ref-cache")
      refDir = next();
    else if (!a.empty() && a[0] != '-')
      scenes.push_back(a);
    else {
      std::fprintf(stderr,
                   "usage: %s [--size N] [--seconds S] [--ref-spp N] [--vpls N] [--threads T] [--csv F] [--images D] "
                   "[--ref-cache D] [scene.gltf ...]\n",
                   argv[0]);
      return a == "--help" ? 0 : 2;
    }
  }
  if (scenes.empty())
    for (const char* name : {"cornell-fog", "fog-shaft"})
      scenes.push_back(std::string(VPLAB_ASSET_DIR) + "/scenes/" + name + ".gltf");
  threads = resolveThreadCount(threads);
  if (!imageDir.empty()) std::filesystem::create_directories(imageDir);
  if (!refDir.empty()) std::filesystem::create_directories(refDir);

  std::vector<Row> rows;
  for (const std::string& path : scenes) {
    const std::string name = std::filesystem::path(path).stem().string();
    OfflineScene offline(loadScene(path));
    const float diagonal = offline.scene().geometryBounds.diagonal();
    Settings base;
    base.width = base.height = size;
    base.threads = threads;
    base.vplCount = vpls;
    base.components = Components::Indirect;
    base.samplesPerPixel = 1;

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
    const std::vector<Variant> variants = {
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
    for (const Variant& v : variants) {
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
        Image sum(size, size);
        double removedSum = 0.0;
        int passes = 0;
        do {
          Settings pass = s;
          pass.seed = s.seed + static_cast<uint32_t>(passes);
          pass.samplesPerPixel = 1;
          VplSet set = generateVpls(offline, pass);
          VplRenderResult one = renderMethod(v.method).render(offline, set, pass, nullptr, {});
          for (std::size_t p = 0; p < sum.pixels.size(); ++p) sum.pixels[p] += one.image.pixels[p];
          removedSum += one.clampEnergyRemoved;
          ++passes;
        } while (now() - start < seconds);
        for (glm::vec3& p : sum.pixels) p /= static_cast<float>(passes);
        r.image = std::move(sum);
        r.samplesPerPixel = passes;
        r.clampEnergyRemoved = removedSum / passes;
      }
      Row row;
      row.scene = name;
      row.method = v.name;
      row.parameters = v.parameters;
      row.seconds = now() - start;
      row.samples = r.samplesPerPixel;
      ImageMetrics m = compareImages(r.image, reference);
      row.relMse = m.relMse;
      row.energy = m.energyRatioOverall;
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

  std::printf("media comparison at equal time (%.0f s each, %dx%d, %d VPLs, indirect light, %d threads)\n", seconds,
              size, size, vpls, threads);
  std::printf("| scene | method | parameters | time (s) | passes | relMSE | energy | bound removed |\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows)
    std::printf("| %s | %s | %s | %.1f | %d | %.4f | %.3f | %.1f %% |\n", r.scene.c_str(), r.method.c_str(),
                r.parameters.c_str(), r.seconds, r.samples, r.relMse, r.energy, 100.0 * r.removed);
  if (!csvPath.empty()) {
    FILE* f = std::fopen(csvPath.c_str(), "w");
    if (!f) {
      std::fprintf(stderr, "cannot write %s\n", csvPath.c_str());
      return 1;
    }
    std::fprintf(f, "scene,method,parameters,seconds,samples,relmse,energy_ratio,bound_removed\n");
    for (const Row& r : rows)
      std::fprintf(f, "%s,%s,%s,%.3f,%d,%.6g,%.6g,%.6g\n", r.scene.c_str(), r.method.c_str(), r.parameters.c_str(),
                   r.seconds, r.samples, r.relMse, r.energy, r.removed);
    std::fclose(f);
  }
  return 0;
}
