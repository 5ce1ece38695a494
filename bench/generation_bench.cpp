// VPL generation benchmark: every generation variant (renderer/vpl/generation_methods.h) at an equal accepted VPL
// count and at equal total time, over several seeds, against a path-traced reference (indirect component, clamped
// CPU VPL renders). Prints per variant: mean relMSE (per pixel and of 4x4 and 16x16 block averages: how much of the
// error is at the pixel scale), mean energy ratio and its spread over the seeds,
// acceptance rate with its spread over the seeds, generation and render time; then the ratios to plain light
// tracing. Times are process CPU time (all threads together), which other processes on a shared machine disturb
// much less than the wall clock; equal time gives plain light tracing as many VPLs as fit in a variant's CPU time.
// docs/methods.md and docs/benchmarks.md record its output.
//   vplab_bench_generation_bench [--size N|WxH] [--vpls N] [--seeds S] [--clamp b] [--epsilon e] [--ref-spp N]
//                                [--threads T] [--cache DIR] [--csv out.csv] [--mir-chains C]
//                                [--variants a,b,...] [scene.gltf ...]
// Defaults: 64x64, 256 VPLs, 8 seeds, b = 100, rejection epsilon 0.05, 4096 reference spp, cornell-box and two-rooms,
// every variant (--variants names some of generationVariants(); plain light tracing, the baseline, always runs).

#include "bench/bench_args.h"
#include "evaluation/harness.h"
#include "renderer/image/metrics.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/vpl/generation_methods.h"
#include "renderer/vpl/vpl_generation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

using namespace vplab;

namespace {

struct Summary {
  double relMse = 0.0, blockRelMse = 0.0, coarseRelMse = 0.0, energy = 0.0, energySpread = 0.0, acceptance = 0.0,
         acceptanceMin = 1e30,
         acceptanceMax = 0.0, genMs = 0.0, renderMs = 0.0, vpls = 0.0;
  double totalMs() const { return genMs + renderMs; }
};

double processCpuMs() { return 1e3 * static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

Summary measure(const OfflineScene& setup, const Image& ref, Settings s, int seeds) {
  Summary sum;
  for (int i = 0; i < seeds; ++i) {
    s.seed = 1000 + static_cast<uint32_t>(i);
    const double c0 = processCpuMs();
    VplSet vpls = generateVpls(setup, s);
    const double c1 = processCpuMs();
    MeasuredImage m = renderCpu(setup, Method::Vpl, vpls, s);
    const double c2 = processCpuMs();
    ImageMetrics px = compareImages(m.image, ref);
    ImageMetrics blk = compareImages(blockAverage(m.image, 4), blockAverage(ref, 4));
    ImageMetrics coarse = compareImages(blockAverage(m.image, 16), blockAverage(ref, 16));
    sum.relMse += px.relMse / seeds;
    sum.blockRelMse += blk.relMse / seeds;
    sum.coarseRelMse += coarse.relMse / seeds;
    sum.energy += px.energyRatioOverall / seeds;
    // Second moment of the energy ratio; the spread over seeds is formed after the loop.
    sum.energySpread += px.energyRatioOverall * px.energyRatioOverall / seeds;
    sum.acceptance += vpls.stats.acceptanceRate / seeds;
    sum.acceptanceMin = std::min(sum.acceptanceMin, vpls.stats.acceptanceRate);
    sum.acceptanceMax = std::max(sum.acceptanceMax, vpls.stats.acceptanceRate);
    sum.genMs += (c1 - c0) / seeds;
    sum.renderMs += (c2 - c1) / seeds;
    sum.vpls += static_cast<double>(vpls.vpls.size()) / seeds;
  }
  sum.energySpread = std::sqrt(std::max(0.0, sum.energySpread - sum.energy * sum.energy));
  return sum;
}

}  // namespace

int main(int argc, char** argv) {
  int width = 64, height = 64, vpls = 256, seeds = 8, refSpp = 4096, threads = 0;
  float clamp = 100.0f, epsilon = 0.05f;
  std::string csvPath, cacheDir = "generation-bench-cache";
  int mirChains = Settings{}.mirChains;
  std::vector<std::string> scenes, only;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--size") {
      const std::string v = benchOptionValue(argc, argv, i);
      width = height = std::atoi(v.c_str());
      if (std::size_t x = v.find('x'); x != std::string::npos) height = std::atoi(v.c_str() + x + 1);
    }
    else if (a == "--vpls") vpls = std::atoi(benchOptionValue(argc, argv, i).c_str());
    else if (a == "--seeds") seeds = std::atoi(benchOptionValue(argc, argv, i).c_str());
    else if (a == "--clamp") clamp = static_cast<float>(std::atof(benchOptionValue(argc, argv, i).c_str()));
    else if (a == "--epsilon") epsilon = static_cast<float>(std::atof(benchOptionValue(argc, argv, i).c_str()));
    else if (a == "--ref-spp") refSpp = std::atoi(benchOptionValue(argc, argv, i).c_str());
    else if (a == "--threads") threads = std::atoi(benchOptionValue(argc, argv, i).c_str());
    else if (a == "--cache") cacheDir = benchOptionValue(argc, argv, i);
    else if (a == "--csv") csvPath = benchOptionValue(argc, argv, i);
    else if (a == "--mir-chains") mirChains = std::atoi(benchOptionValue(argc, argv, i).c_str());
    else if (a == "--variants") {
      const std::string list = benchOptionValue(argc, argv, i);
      for (std::size_t begin = 0; begin <= list.size();) {
        std::size_t end = std::min(list.find(',', begin), list.size());
        const std::string name = list.substr(begin, end - begin);
        if (!findGenerationVariant(name)) {
          std::fprintf(stderr, "%s: --variants: no generation variant named '%s'\n", argv[0], name.c_str());
          return 2;
        }
        only.push_back(name);
        begin = end + 1;
      }
    }
    else if (a.rfind("--", 0) == 0) {
      std::fprintf(stderr, "%s: unknown option %s\n", argv[0], a.c_str());
      return 2;
    } else scenes.push_back(a);
  }
  if (width < 4 || height < 4 || vpls < 1 || seeds < 1 || refSpp < 1) {
    std::fprintf(stderr, "%s: --size >= 4 (N or WxH), --vpls, --seeds and --ref-spp >= 1\n", argv[0]);
    return 2;
  }
  if (scenes.empty()) scenes = {"assets/scenes/cornell-box.gltf", "assets/scenes/two-rooms.gltf"};
  std::FILE* csv = csvPath.empty() ? nullptr : std::fopen(csvPath.c_str(), "w");
  if (!csvPath.empty() && !csv) {
    std::fprintf(stderr, "%s: cannot write %s\n", argv[0], csvPath.c_str());
    return 1;
  }
  if (csv)
    std::fprintf(csv, "scene,variant,comparison,vpls,seeds,relmse,block_relmse,energy_ratio,acceptance,"
                      "acceptance_min,acceptance_max,gen_ms,render_ms\n");
  std::printf("%dx%d, indirect, clamp b = %g, %d seeds, reference %d spp, rejection epsilon %g, times: process CPU\n",
              width, height, clamp, seeds, refSpp, epsilon);
  for (const std::string& path : scenes) {
    OfflineScene setup(loadScene(path));
    Settings base;
    base.width = width;
    base.height = height;
    base.threads = threads;
    base.components = Components::Indirect;
    base.samplesPerPixel = 1;
    base.clampBound = clamp;
    base.rejectionEpsilon = epsilon;
    base.mirChains = mirChains;
    Settings refSettings = base;
    refSettings.samplesPerPixel = refSpp;
    Image ref = cachedReference(setup, sceneStem(path), refSettings, cacheDir).image;
    std::printf("\n%s\n%-26s %-10s %6s %9s %9s %7s %18s %9s %9s %8s %8s\n", sceneStem(path).c_str(), "variant",
                "at", "VPLs", "relMSE", "4x4 rel", "energy", "acceptance (range)", "gen ms", "render ms",
                "x relMSE", "x 4x4");
    Summary plain;
    for (const GenerationVariant& v : generationVariants()) {
      const bool isPlain = v.generation == VplGeneration::Light && !v.rejection;
      if (!isPlain && !only.empty() && std::find(only.begin(), only.end(), v.name) == only.end()) continue;
      Settings s = base;
      applyGenerationVariant(v, s);
      s.vplCount = vpls;
      Summary m = measure(setup, ref, s, seeds);
      if (v.generation == VplGeneration::Light && !v.rejection) plain = m;
      std::vector<std::pair<std::string, Summary>> rows = {{"equal N", m}};
      // Equal total time: plain light tracing with as many VPLs as fit in this variant's CPU time (render time grows
      // linearly with N, generation is negligible for plain light tracing).
      if (!(v.generation == VplGeneration::Light && !v.rejection) && plain.totalMs() > 0.0) {
        Settings p = base;
        p.vplCount = std::max(1, static_cast<int>(std::lround(vpls * m.totalMs() / plain.totalMs())));
        rows.push_back({"equal time", measure(setup, ref, p, seeds)});
      }
      for (auto& [at, r] : rows) {
        const Summary& shown = at == "equal N" ? m : r;
        double ratio = plain.relMse > 0 ? m.relMse / (at == "equal N" ? plain.relMse : r.relMse) : 0.0;
        double ratioBlock = plain.blockRelMse > 0 ? m.blockRelMse / (at == "equal N" ? plain.blockRelMse
                                                                                      : r.blockRelMse)
                                                  : 0.0;
        std::string name = at == "equal N" ? v.label : std::string("  light tracing, same time");
        char acc[64];
        std::snprintf(acc, sizeof acc, "%.3f (%.3f-%.3f)", shown.acceptance, shown.acceptanceMin,
                      shown.acceptanceMax);
        std::printf("%-26s %-10s %6.0f %9.4g %9.4g %7.3f %18s %9.1f %9.1f %8.3f %8.3f\n", name.c_str(), at.c_str(),
                    shown.vpls, shown.relMse, shown.blockRelMse, shown.energy, acc, shown.genMs, shown.renderMs,
                    ratio, ratioBlock);
        std::printf("%-26s %-10s 16x16 relMSE %.4g, energy spread over seeds %.3f\n", "", "", shown.coarseRelMse,
                    shown.energySpread);
        if (csv)
          std::fprintf(csv, "%s,%s,%s,%.0f,%d,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g\n", sceneStem(path).c_str(),
                       v.name, at == "equal N" ? "equal-count" : "plain-at-equal-time", shown.vpls, seeds,
                       shown.relMse, shown.blockRelMse, shown.energy, shown.acceptance, shown.acceptanceMin,
                       shown.acceptanceMax, shown.genMs, shown.renderMs);
      }
    }
  }
  if (csv && std::fclose(csv) != 0) {
    std::fprintf(stderr, "%s: write failed: %s\n", argv[0], csvPath.c_str());
    return 1;
  }
  if (csv) std::printf("\nwrote %s\n", csvPath.c_str());
  return 0;
}
