#pragma once
// Speed-versus-accuracy sweeps (docs/theory.md §10): every many-light method (plain VPLs, clamp, clamp + SSBC,
// VSL, rejection, Kollig-Keller) on the CPU and in the GL preview, over its parameters (N, b, r, epsilon, k,
// shadow-map size), each run measured as time and error against a path-traced reference. Writes bench.csv (one row
// per run, flushed as measured; a restart with the same output folder skips the rows already there), SVG charts and
// report.md with the images.

#include <functional>
#include <string>
#include <vector>

#include "evaluation/csv_log.h"
#include "evaluation/harness.h"
#include "renderer/settings.h"

namespace vplab {

/// Method names used in bench.csv and --methods: the rendering variants of light-traced VPLs (vpl, clamp, ssbc,
/// vsl, vpl-kk) and the generation variants of renderer/vpl/generation_methods.h (reject, bidirectional, ...).
const std::vector<std::string>& benchMethodNames();

/// Position of a method in benchMethodNames() (its colour in every chart, the editor's included); -1 if unknown.
inline int benchMethodIndex(const std::string& method) {
  const auto& names = benchMethodNames();
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == method) return static_cast<int>(i);
  return -1;
}

/// Colour (0xRRGGBB) of a method in benchMethodNames() in every chart and in the editor's VPL overlay, which rings
/// the VPLs in their generation variant's colour.
unsigned benchMethodColourRgb(const std::string& method);

/// Marker shape of a backend in every chart: circles for the CPU renders, squares for the GL preview.
inline int benchBackendShape(bool gl) { return gl ? 1 : 0; }

struct BenchConfig {
  std::string outDir = "bench-out";
  int width = 128;
  int height = 128;
  bool quick = false;                ///< fewer parameter values and VPLs
  std::vector<std::string> methods;  ///< subset of benchMethodNames(); empty = all
  int referenceSpp = 1024;           ///< samples per pixel of the reference
  int cpuSpp = 4;                    ///< samples per pixel of the CPU VPL renders (anti-aliasing, KK's paths)
  Components components = Components::Indirect;  ///< what is compared: the indirect part (default) or everything
  bool gl = true;                                ///< run the GL variants (skipped with a note when no context)
  GlBackend glBackend = GlBackend::Auto;
  uint32_t seed = 1;
  int threads = 0;
  bool writeImages = true;  ///< per-run PNG and relative-error heatmap under images/
  /// A deterministic part of the sweep: run k (counted over every scene's cases, in order) belongs to shard
  /// k mod shardCount. Shards write their own bench.csv and no report; mergeBench() joins them. [0, shardCount).
  int shardIndex = 0;
  int shardCount = 1;
  /// How each scene file is loaded (harness.h); empty: as it is.
  SceneLoader loadScene;
  /// Progress lines (stderr in the CLI). May be empty.
  std::function<void(const std::string&)> log;
};

/// One point of the sweep: a method on a backend with full settings.
struct BenchCase {
  std::string method;  ///< one of benchMethodNames()
  Backend backend = Backend::Cpu;
  Settings settings;
};

/// The cases of one scene, in the order they are run. Parameter values scale with the scene: clamp bounds are
/// b = 1 / (f D)^2 (the residual's radius 1/sqrt(b) a fraction f of the scene diagonal D), VSL radii r = f D.
std::vector<BenchCase> benchCases(const Scene& scene, const BenchConfig& config);

/// Columns of bench.csv: the key (scene, method, backend, every parameter) then the measurements.
const std::vector<std::string>& benchCsvHeader();
/// Number of leading columns of benchCsvHeader() that identify a run.
std::size_t benchCsvKeyColumns();

struct BenchOutcome {
  std::string csvPath;
  std::string reportPath;
  std::vector<std::string> charts;  ///< every SVG written
  std::size_t rowsMeasured = 0;     ///< measured in this call
  std::size_t rowsReused = 0;       ///< found in bench.csv from an earlier call
  std::string glNote;               ///< why GL rows are missing, empty when they ran
};

/// Runs the sweep on every scene file and writes the outputs under config.outDir. Throws (SceneError, ImageIoError,
/// CsvError) on runtime failures, naming the file.
BenchOutcome runBench(const std::vector<std::string>& scenePaths, const BenchConfig& config);

/// Joins the bench.csv (and per-run images) of shard folders into config.outDir, then writes its charts and
/// report.md. Rows already in config.outDir/bench.csv are kept and a row of a run already there is not added again,
/// so merging twice, or merging into a folder an unsharded sweep wrote, changes nothing. Throws CsvError when a shard
/// has another header or the shards compared different components.
BenchOutcome mergeBench(const std::vector<std::string>& shardDirs, BenchConfig config);

/// Rewrites the charts and report.md of config.outDir from its bench.csv (what runBench does at its end).
BenchOutcome writeBenchReport(const std::vector<std::string>& sceneNames, const BenchConfig& config);

}  // namespace vplab
