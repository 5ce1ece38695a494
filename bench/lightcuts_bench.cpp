// Lightcuts against the exact VPL sum on the same VPLs (docs/benchmarks.md "Lightcuts"). Per VPL count N and
// threshold: the light tree's build time (median of 3 builds), the lightcut render's time (tree included), mean cut
// size and shadow rays per cut, and its per-pixel relative error against renderVpl's exact sum of the same VPLs
// (luminance, over the pixels the VPLs light): mean, 95th percentile, and the energy ratio. Both render the indirect
// part only (the only part lightcuts changes), one sample per pixel, with the same camera samples.
//
// The exact sum costs N evaluations per pixel: from --exact-limit VPLs on (default 300000) it is rendered at a
// reduced size (--exact-size, default 64: the same view on 64x64 pixels) and its time scaled by the pixel count; the
// errors at that N compare lightcuts and the exact sum on that reduced image (the speed-up takes lightcuts' time at
// the full size).
//
// usage: vplab_bench_lightcuts_bench [--scene file.gltf] [--size N] [--vpls 100000,1000000]
//                                    [--thresholds 0.01,0.005] [--clamp-bound B] [--exact-limit N] [--exact-size N]
//                                    [--threads T] [--csv out.csv]

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bench_args.h"
#include "renderer/core/parallel.h"
#include "renderer/core/sampling.h"
#include "renderer/offline/lightcuts_renderer.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/scene/brdf_params.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/vpl/vpl_generation.h"

namespace {

using namespace vplab;

std::vector<double> parseList(const std::string& text) {
  std::vector<double> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) out.push_back(std::stod(item));
  return out;
}

struct ErrorStats {
  double mean = 0.0, p95 = 0.0, energy = 0.0;
};

/// Per-pixel relative error of `image` against `exact` (luminance), over the pixels exact lights.
ErrorStats compare(const Image& image, const Image& exact) {
  std::vector<double> rel;
  double sumImage = 0.0, sumExact = 0.0;
  for (std::size_t i = 0; i < exact.pixels.size(); ++i) {
    const double e = luminance(exact.pixels[i]), c = luminance(image.pixels[i]);
    sumImage += c, sumExact += e;
    if (e > 0.0) rel.push_back(std::abs(c - e) / e);
  }
  ErrorStats s;
  if (rel.empty()) return s;
  for (double r : rel) s.mean += r;
  s.mean /= static_cast<double>(rel.size());
  std::sort(rel.begin(), rel.end());
  s.p95 = rel[std::min(rel.size() - 1, static_cast<std::size_t>(0.95 * static_cast<double>(rel.size())))];
  s.energy = sumExact > 0.0 ? sumImage / sumExact : 0.0;
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  std::string scenePath = "assets/scenes/cornell-box.gltf", csvPath = "lightcuts_bench.csv";
  int size = 256, exactSize = 64, threads = 0;
  double exactLimit = 300000;
  float clampBound = 10.0f;
  std::vector<double> counts = {100000, 1000000}, thresholds = {0.01, 0.005};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--scene") scenePath = benchOptionValue(argc, argv, i);
    else if (a == "--size") size = std::stoi(benchOptionValue(argc, argv, i));
    else if (a == "--vpls") counts = parseList(benchOptionValue(argc, argv, i));
    else if (a == "--thresholds") thresholds = parseList(benchOptionValue(argc, argv, i));
    else if (a == "--clamp-bound") clampBound = std::stof(benchOptionValue(argc, argv, i));
    else if (a == "--exact-limit") exactLimit = std::stod(benchOptionValue(argc, argv, i));
    else if (a == "--exact-size") exactSize = std::stoi(benchOptionValue(argc, argv, i));
    else if (a == "--threads") threads = std::stoi(benchOptionValue(argc, argv, i));
    else if (a == "--csv") csvPath = benchOptionValue(argc, argv, i);
    else {
      std::fprintf(stderr, "%s: unknown option %s\n", argv[0], a.c_str());
      return 2;
    }
  }
  const Scene scene = loadScene(scenePath);
  const OfflineScene offline(scene);
  std::FILE* csv = std::fopen(csvPath.c_str(), "w");
  if (!csv) {
    std::fprintf(stderr, "%s: cannot write %s\n", argv[0], csvPath.c_str());
    return 1;
  }
  std::fprintf(csv,
               "scene,vpls,threshold,clamp_b,width,threads,tree_ms,tree_mb,lightcuts_ms,exact_ms,exact_width,speedup,"
               "mean_cut,mean_rays,cuts_at_max,mean_rel_err,p95_rel_err,energy_ratio\n");
  std::printf("%-9s %-9s %-8s %-8s %-11s %-11s %-8s %-9s %-9s %-8s %-8s %-8s %-7s\n", "vpls", "threshold", "tree ms",
              "tree MB", "lc ms", "exact ms", "exact px", "speed-up", "mean cut", "rays", "mean err", "p95 err",
              "energy");
  for (double countValue : counts) {
    Settings s;
    s.width = s.height = size;
    s.vplCount = static_cast<int>(countValue);
    s.clampBound = clampBound;
    s.components = Components::Indirect;
    s.samplesPerPixel = 1;
    s.threads = threads;
    const VplSet vpls = generateVpls(offline, s);
    // The tree alone: the median of three builds.
    std::vector<BrdfParams> brdfs;
    for (const Vpl& v : vpls.vpls) brdfs.push_back(brdfParamsAt(scene, v.material, v.uv));
    std::vector<double> builds;
    for (int k = 0; k < 3; ++k)
      builds.push_back(LightTree(vpls.vpls, brdfs, s.seed, resolveThreadCount(threads)).buildSeconds());
    std::sort(builds.begin(), builds.end());
    const double treeMb = (2.0 * static_cast<double>(vpls.vpls.size()) - 1.0) * sizeof(LightTreeNode) / 1e6;
    // The exact sum: full size, or the same view at exactSize with the time scaled by the pixel count.
    const bool reduced = static_cast<double>(vpls.vpls.size()) >= exactLimit;
    Settings exactSettings = s;
    if (reduced) exactSettings.width = exactSettings.height = exactSize;
    const VplRenderResult exact = renderVpl(offline, vpls, Method::Vpl, exactSettings);
    const double exactScale =
        static_cast<double>(size) * size / (static_cast<double>(exactSettings.width) * exactSettings.height);
    const double exactMs = 1e3 * exact.seconds * exactScale;
    for (double threshold : thresholds) {
      s.lightcutError = static_cast<float>(threshold);
      const LightcutsRenderResult cut = renderLightcuts(offline, vpls, Method::Lightcuts, s);
      ErrorStats err;
      if (reduced) {
        Settings small = exactSettings;
        small.lightcutError = s.lightcutError;
        err = compare(renderLightcuts(offline, vpls, Method::Lightcuts, small).image, exact.image);
      } else {
        err = compare(cut.image, exact.image);
      }
      const double lcMs = 1e3 * cut.seconds;
      std::printf("%-9zu %-9.4g %-8.1f %-8.1f %-11.1f %-11.0f %-8d %-9.1f %-9.1f %-8.1f %-8.4f %-8.4f %-7.4f\n",
                  vpls.vpls.size(), threshold, 1e3 * builds[1], treeMb, lcMs, exactMs, exactSettings.width,
                  exactMs / lcMs, cut.meanCut, cut.meanShadowRays, err.mean, err.p95, err.energy);
      std::fprintf(csv, "%s,%zu,%g,%g,%d,%d,%.2f,%.1f,%.1f,%.0f,%d,%.2f,%.2f,%.2f,%llu,%.5f,%.5f,%.5f\n",
                   scenePath.c_str(), vpls.vpls.size(), threshold, clampBound, size, resolveThreadCount(threads),
                   1e3 * builds[1], treeMb, lcMs, exactMs, exactSettings.width, exactMs / lcMs, cut.meanCut,
                   cut.meanShadowRays, static_cast<unsigned long long>(cut.cutsAtMax), err.mean, err.p95, err.energy);
      std::fflush(stdout);
    }
  }
  std::fclose(csv);
  std::printf("wrote %s\n", csvPath.c_str());
  return 0;
}
