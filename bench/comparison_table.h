#pragma once
// What the equal-time method comparisons (media_bench, glossy_bench) share: their common options, the rows of methods
// they render, and their table and CSV (one row per scene and method).

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <string>
#include <vector>

#include "bench/bench_args.h"
#include "renderer/core/parallel.h"
#include "renderer/image/image.h"
#include "renderer/image/metrics.h"
#include "renderer/settings.h"

namespace vplab {

/// The options both comparisons take; each sets its own defaults before parsing.
struct ComparisonOptions {
  std::vector<std::string> scenes;
  std::string csvPath, imageDir, refDir;
  int size = 128, refSpp = 4096, vpls = 256, threads = 0;
  double seconds = 10.0;
};
inline constexpr const char* kComparisonUsage =
    "[--size N] [--seconds S] [--ref-spp N] [--vpls N] [--threads T] [--csv F] [--images D] [--ref-cache D]";

/// Takes argv[i] when it is a common option (and its value, advancing i) or a scene path: true when it was.
inline bool parseComparisonOption(int argc, char** argv, int& i, ComparisonOptions& o) {
  const std::string a = argv[i];
  auto next = [&] { return benchOptionValue(argc, argv, i); };
  if (a == "--size")
    o.size = std::atoi(next().c_str());
  else if (a == "--seconds")
    o.seconds = std::atof(next().c_str());
  else if (a == "--ref-spp")
    o.refSpp = std::atoi(next().c_str());
  else if (a == "--vpls")
    o.vpls = std::atoi(next().c_str());
  else if (a == "--threads")
    o.threads = std::atoi(next().c_str());
  else if (a == "--csv")
    o.csvPath = next();
  else if (a == "--images")
    o.imageDir = next();
  else if (a == "--ref-cache")
    o.refDir = next();
  else if (!a.empty() && a[0] != '-')
    o.scenes.push_back(a);
  else
    return false;
  return true;
}

/// After parsing: the default scenes (assets/scenes/<name>.gltf) when none was named, the thread count resolved, the
/// image directory created.
inline void prepareComparison(ComparisonOptions& o, std::initializer_list<const char*> defaultScenes) {
  if (o.scenes.empty())
    for (const char* name : defaultScenes)
      o.scenes.push_back(std::string(VPLAB_ASSET_DIR) + "/scenes/" + name + ".gltf");
  o.threads = resolveThreadCount(o.threads);
  if (!o.imageDir.empty()) std::filesystem::create_directories(o.imageDir);
}

/// The settings every row starts from: the image size, threads and VPLs per pass of the options, indirect light,
/// one pixel sample per pass.
inline Settings comparisonBase(const ComparisonOptions& o) {
  Settings base;
  base.width = base.height = o.size;
  base.threads = o.threads;
  base.vplCount = o.vpls;
  base.components = Components::Indirect;
  base.samplesPerPixel = 1;
  return base;
}

/// One table row: the method's settings differ from the base by `edit`.
struct ComparisonVariant {
  std::string name;  ///< the table's row name
  Method method;
  std::string parameters;
  std::function<void(Settings&)> edit;
};

struct ComparisonRow {
  std::string scene, method, parameters;
  double seconds = 0.0;
  int passes = 0;
  double relMse = 0.0;
  double blockRelMse = 0.0;  ///< relMSE of 4x4-pixel block averages: the reference's own noise kept out
  double energy = 0.0;       ///< mean(I) / mean(R)
  double removed = 0.0;      ///< the bound's share of the VPL energy (0 without one)
};

/// A row's measures of `image` against `reference`.
inline ComparisonRow measureComparison(const Image& image, const Image& reference) {
  ComparisonRow row;
  const ImageMetrics m = compareImages(image, reference);
  row.relMse = m.relMse;
  row.energy = m.energyRatioOverall;
  row.blockRelMse = compareImages(blockAverage(image, 4), blockAverage(reference, 4)).relMse;
  return row;
}

/// Prints the rows as a Markdown table under `title`; writes them to csvPath unless it is empty. False when the CSV
/// cannot be written (said on stderr).
inline bool reportComparison(const std::string& title, const std::vector<ComparisonRow>& rows,
                             const std::string& csvPath) {
  std::printf("%s\n", title.c_str());
  std::printf("| scene | method | parameters | time (s) | passes | relMSE | 4x4 relMSE | energy | bound removed |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  for (const ComparisonRow& r : rows)
    std::printf("| %s | %s | %s | %.1f | %d | %.4f | %.4f | %.3f | %.1f %% |\n", r.scene.c_str(), r.method.c_str(),
                r.parameters.c_str(), r.seconds, r.passes, r.relMse, r.blockRelMse, r.energy, 100.0 * r.removed);
  if (csvPath.empty()) return true;
  FILE* f = std::fopen(csvPath.c_str(), "w");
  if (!f) {
    std::fprintf(stderr, "cannot write %s\n", csvPath.c_str());
    return false;
  }
  std::fprintf(f, "scene,method,parameters,seconds,samples,relmse,relmse_4x4,energy_ratio,bound_removed\n");
  for (const ComparisonRow& r : rows)
    std::fprintf(f, "%s,%s,%s,%.3f,%d,%.6g,%.6g,%.6g,%.6g\n", r.scene.c_str(), r.method.c_str(), r.parameters.c_str(),
                 r.seconds, r.passes, r.relMse, r.blockRelMse, r.energy, r.removed);
  std::fclose(f);
  return true;
}

}  // namespace vplab
