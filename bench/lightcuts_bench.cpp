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
// Matrix row-column sampling (mrcs_renderer.h) gets rows for each --mrcs rows/clusters pair (default 100/300,300/900)
// at VPL counts up to --mrcs-limit (default 300000: its rows x VPLs matrix takes rows x N floats); its "cut" column is
// the cluster count and its time includes the rows and the clustering. A model without lights is staged in the studio
// (renderer/scene/staging.h); --clamp-bound-relative B sets b = B / diagonal^2 of the scene instead of --clamp-bound.
//
// --svg PREFIX writes two charts against N (log-log, evaluation/svg_chart.h): PREFIX-time.svg, the time of the exact
// sum (scaled as above from --exact-limit VPLs on) and of each lightcuts and mrcs row, and PREFIX-error.svg, their
// mean per-pixel error.
//
// usage: vplab_bench_lightcuts_bench [--scene file.gltf] [--size N] [--vpls 100000,1000000]
//                                    [--thresholds 0.01,0.005] [--mrcs R/K,...] [--mrcs-limit N] [--clamp-bound B]
//                                    [--clamp-bound-relative B]
//                                    [--exact-limit N] [--exact-size N] [--threads T] [--csv out.csv]
//                                    [--svg prefix]

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bench_args.h"
#include "evaluation/svg_chart.h"
#include "renderer/core/parallel.h"
#include "renderer/core/sampling.h"
#include "renderer/image/metrics.h"
#include "renderer/offline/lightcuts_renderer.h"
#include "renderer/offline/mrcs_renderer.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/scene/brdf_params.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/staging.h"
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

}  // namespace

int main(int argc, char** argv) {
  std::string scenePath = "assets/scenes/cornell-box.gltf", csvPath = "lightcuts_bench.csv", svgPrefix;
  // The charts' series by name: (N, time in s) and (N, mean error in %).
  std::map<std::string, ChartSeries> timeSeries, errorSeries;
  auto chartPoint = [&](const std::string& name, double n, double seconds, double meanError) {
    timeSeries[name].name = errorSeries[name].name = name;
    timeSeries[name].points.push_back({n, seconds});
    if (meanError >= 0.0) errorSeries[name].points.push_back({n, 100.0 * meanError});
  };
  int size = 256, exactSize = 64, threads = 0;
  double exactLimit = 300000;
  float clampBound = 10.0f, clampBoundRelative = 0.0f;
  std::vector<double> counts = {100000, 1000000}, thresholds = {0.01, 0.005};
  std::vector<std::pair<int, int>> mrcs = {{100, 300}, {300, 900}};
  double mrcsLimit = 300000;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--scene")
      scenePath = benchOptionValue(argc, argv, i);
    else if (a == "--size")
      size = std::stoi(benchOptionValue(argc, argv, i));
    else if (a == "--vpls")
      counts = parseList(benchOptionValue(argc, argv, i));
    else if (a == "--thresholds")
      thresholds = parseList(benchOptionValue(argc, argv, i));
    else if (a == "--clamp-bound")
      clampBound = std::stof(benchOptionValue(argc, argv, i));
    else if (a == "--clamp-bound-relative")
      clampBoundRelative = std::stof(benchOptionValue(argc, argv, i));
    else if (a == "--exact-limit")
      exactLimit = std::stod(benchOptionValue(argc, argv, i));
    else if (a == "--exact-size")
      exactSize = std::stoi(benchOptionValue(argc, argv, i));
    else if (a == "--mrcs") {
      mrcs.clear();
      std::stringstream in(benchOptionValue(argc, argv, i));
      std::string item;
      while (std::getline(in, item, ','))
        mrcs.push_back({std::stoi(item.substr(0, item.find('/'))), std::stoi(item.substr(item.find('/') + 1))});
    } else if (a == "--mrcs-limit")
      mrcsLimit = std::stod(benchOptionValue(argc, argv, i));
    else if (a == "--threads")
      threads = std::stoi(benchOptionValue(argc, argv, i));
    else if (a == "--csv")
      csvPath = benchOptionValue(argc, argv, i);
    else if (a == "--svg")
      svgPrefix = benchOptionValue(argc, argv, i);
    else {
      std::fprintf(stderr, "%s: unknown option %s\n", argv[0], a.c_str());
      return 2;
    }
  }
  // A model without lights gets the studio, as the commands stage it (Stage::Auto).
  Scene scene = loadScene(scenePath);
  stageScene(scene, Stage::Auto);
  const OfflineScene offline(scene);
  std::FILE* csv = std::fopen(csvPath.c_str(), "w");
  if (!csv) {
    std::fprintf(stderr, "%s: cannot write %s\n", argv[0], csvPath.c_str());
    return 1;
  }
  std::fprintf(csv,
               "scene,vpls,method,parameters,clamp_b,width,threads,tree_ms,tree_mb,render_ms,exact_ms,exact_width,"
               "speedup,mean_cut,mean_rays,cuts_at_max,mean_rel_err,p95_rel_err,energy_ratio\n");
  std::printf("%-8s %-10s %-13s %-7s %-7s %-9s %-9s %-6s %-8s %-8s %-7s %-8s %-8s %-7s\n", "vpls", "method",
              "parameters", "tree ms", "tree MB", "ms", "exact ms", "ex. px", "speed-up", "cut", "rays", "mean err",
              "p95 err", "energy");
  for (double countValue : counts) {
    Settings s;
    s.width = s.height = size;
    s.vplCount = static_cast<int>(countValue);
    s.clampBound = clampBound;
    s.clampBoundRelative = clampBoundRelative;
    resolveClampBound(s, scene.geometryBounds.diagonal());
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
    chartPoint("exact sum", static_cast<double>(vpls.vpls.size()), exactMs / 1e3, -1.0);
    // One row: `render` renders at the given settings; its errors are taken at the exact sum's size.
    auto row = [&](const char* method, const std::string& parameters, const Settings& rs, auto render) {
      const auto full = render(rs);
      PixelRelativeError err;
      if (reduced) {
        Settings small = rs;
        small.width = exactSettings.width, small.height = exactSettings.height;
        err = pixelRelativeError(render(small).image, exact.image);
      } else {
        err = pixelRelativeError(full.image, exact.image);
      }
      const double ms = 1e3 * full.seconds;
      const double lit = full.cuts;
      const double cut = lit > 0 ? full.meanCut : 0.0, rays = lit > 0 ? full.meanShadowRays : 0.0;
      std::printf("%-8zu %-10s %-13s %-7.1f %-7.1f %-9.1f %-9.0f %-6d %-8.1f %-8.1f %-7.1f %-8.4f %-8.4f %-7.4f\n",
                  vpls.vpls.size(), method, parameters.c_str(), 1e3 * builds[1], treeMb, ms, exactMs,
                  exactSettings.width, exactMs / ms, cut, rays, err.mean, err.p95, err.energyRatio);
      std::fprintf(csv, "%s,%zu,%s,%s,%g,%d,%d,%.2f,%.1f,%.1f,%.0f,%d,%.2f,%.2f,%.2f,%llu,%.5f,%.5f,%.5f\n",
                   scenePath.c_str(), vpls.vpls.size(), method, parameters.c_str(), s.clampBound, size,
                   resolveThreadCount(threads), 1e3 * builds[1], treeMb, ms, exactMs, exactSettings.width, exactMs / ms,
                   cut, rays, static_cast<unsigned long long>(full.cutsAtMax), err.mean, err.p95, err.energyRatio);
      std::fflush(stdout);
      std::fflush(csv);
      chartPoint(std::string(method) + " " + parameters, static_cast<double>(vpls.vpls.size()), ms / 1e3, err.mean);
    };
    for (double threshold : thresholds) {
      Settings rs = s;
      rs.lightcutError = static_cast<float>(threshold);
      row("lightcuts", "e=" + std::to_string(threshold).substr(0, 5), rs,
          [&](const Settings& t) { return renderLightcuts(offline, vpls, Method::Lightcuts, t); });
    }
    if (static_cast<double>(vpls.vpls.size()) > mrcsLimit) continue;
    for (const auto& [rows, clusters] : mrcs) {
      Settings rs = s;
      rs.mrcsRows = rows, rs.mrcsClusters = clusters;
      row("mrcs", std::to_string(rows) + "/" + std::to_string(clusters), rs, [&](const Settings& t) {
        // Cut statistics for MRCS: one "node" and at most one shadow ray per cluster and pixel sample.
        LightcutsRenderResult r;
        const MrcsRenderResult m = renderMrcs(offline, vpls, t);
        static_cast<VplRenderResult&>(r) = m;
        r.cuts = 1;
        r.meanCut = static_cast<double>(m.reduction.reduced.vpls.size());
        r.meanShadowRays = static_cast<double>(m.shadowRays) / (static_cast<double>(t.width) * t.height);
        return r;
      });
    }
  }
  std::fclose(csv);
  std::printf("wrote %s\n", csvPath.c_str());
  if (!svgPrefix.empty()) {
    const std::string title = scenePath.substr(scenePath.find_last_of('/') + 1) + ", " + std::to_string(size) + "^2";
    ChartSpec time{title + ": time against N", "VPLs N", "seconds", true, true, {}, {}};
    ChartSpec error{
        title + ": mean per-pixel error against the exact sum", "VPLs N", "mean error (%)", true, true, {}, {}};
    for (auto& [name, series] : timeSeries) time.series.push_back(series);
    for (auto& [name, series] : errorSeries)
      if (!series.points.empty()) error.series.push_back(series);
    writeSvgChart(svgPrefix + "-time.svg", time);
    writeSvgChart(svgPrefix + "-error.svg", error);
    std::printf("wrote %s-time.svg, %s-error.svg\n", svgPrefix.c_str(), svgPrefix.c_str());
  }
  return 0;
}
