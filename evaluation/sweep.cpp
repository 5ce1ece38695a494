#include "evaluation/sweep.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "evaluation/svg_chart.h"
#include "renderer/core/atomic_file.h"
#include "renderer/core/fnv1a.h"
#include "renderer/image/heatmap.h"
#include "renderer/image/image_io.h"
#include "renderer/image/metrics.h"
#include "renderer/offline/render_methods.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/vpl/generation_methods.h"
#include "renderer/vpl/vpl_generation.h"

namespace vplab {

namespace {

namespace fs = std::filesystem;

std::string fmt(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  if (std::isnan(v)) return "nan";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

// Two significant digits: parameter values derived from the scene size read better rounded.
float round2(float v) {
  if (!(v > 0.0f) || !std::isfinite(v)) return v;
  double mag = std::pow(10.0, std::floor(std::log10(v)) - 1.0);
  return static_cast<float>(std::round(v / mag) * mag);
}

double toDouble(const std::string& s) {
  if (s == "inf") return std::numeric_limits<double>::infinity();
  if (s == "-inf") return -std::numeric_limits<double>::infinity();
  try {
    return std::stod(s);
  } catch (...) {
    return std::numeric_limits<double>::quiet_NaN();
  }
}


bool wanted(const BenchConfig& config, const std::string& method) {
  return config.methods.empty() ||
         std::find(config.methods.begin(), config.methods.end(), method) != config.methods.end();
}

std::vector<std::string> keyOf(const std::string& scene, const BenchCase& c, const BenchConfig& config) {
  const Settings& s = c.settings;
  return {scene,
          c.method,
          toString(c.backend),
          toString(s.components),
          std::to_string(s.width),
          std::to_string(s.height),
          std::to_string(s.seed),
          std::to_string(s.vplCount),
          std::to_string(s.vplMaxBounces),
          fmt(s.clampBound),
          fmt(s.vslRadius),
          s.rejection ? "1" : "0",
          s.rejection ? fmt(s.rejectionEpsilon) : "",
          std::to_string(s.interleave),
          std::to_string(s.ssbcSteps),
          std::to_string(s.shadowMapSize),
          c.backend == Backend::Cpu ? std::to_string(s.samplesPerPixel) : "1",
          std::to_string(config.referenceSpp)};
}

std::string generationKey(const Settings& s) {
  return std::string(toString(s.generation)) + "|" + std::to_string(s.vplCount) + "|" +
         std::to_string(s.vplMaxBounces) + "|" + std::to_string(s.seed) + "|" +
         (s.rejection ? fmt(s.rejectionEpsilon) : "off") + "|" + fmt(s.vslRadius) + "|" +
         std::to_string(s.vslRadiusFromDensity);
}

void say(const BenchConfig& config, const std::string& line) {
  if (config.log) config.log(line);
}

// An empty series of one method on one backend: named, coloured by the method and shaped by the backend.
ChartSeries methodSeries(const std::string& method, const std::string& backend) {
  ChartSeries s;
  s.name = method + " (" + backend + ")";
  s.colour = benchMethodIndex(method);
  s.shape = benchBackendShape(backend == "gl");
  return s;
}

// Order of the series in every chart and table: the method list, CPU before GL.
int seriesRank(const std::string& method, const std::string& backend) {
  const auto& names = benchMethodNames();
  int m = static_cast<int>(std::find(names.begin(), names.end(), method) - names.begin());
  return 2 * m + (backend == "gl" ? 1 : 0);
}

std::string describeRow(const CsvRow& r) {
  const std::string& m = r.at("method");
  std::string d = "N=" + r.at("vpls");
  if (m == "clamp" || m == "ssbc" || m == "vpl-kk" || m == "vpl-abc" || m == "lvl" || m == "lightcuts" ||
      m == "mrcs")
    d += " b=" + r.at("clamp_b");
  if (m == "ssbc") d += " s=" + r.at("ssbc");
  if (m == "vsl") d += " r=" + r.at("vsl_r");
  if (m == "reject") d += " eps=" + r.at("epsilon");
  if (r.at("interleave") != "1") d += " k=" + r.at("interleave");
  if (r.at("backend") == "gl" && r.at("shadow_map") != std::to_string(Settings{}.shadowMapSize))
    d += " sm=" + r.at("shadow_map");
  return d;
}

// " +- spread" where the pilot predicted one (rejection), else nothing.
std::string spreadOf(const CsvRow& r) {
  auto it = r.find("acceptance_spread");
  if (it == r.end() || it->second.empty() || toDouble(it->second) <= 0.0) return "";
  return " ± " + it->second;
}

struct SeriesKey {
  std::string method, backend;
  bool operator<(const SeriesKey& o) const {
    int a = seriesRank(method, backend), b = seriesRank(o.method, o.backend);
    return a != b ? a < b : std::tie(method, backend) < std::tie(o.method, o.backend);
  }
};

std::map<SeriesKey, std::vector<const CsvRow*>> groupRows(const std::vector<const CsvRow*>& rows) {
  std::map<SeriesKey, std::vector<const CsvRow*>> groups;
  for (const CsvRow* r : rows) groups[{r->at("method"), r->at("backend")}].push_back(r);
  return groups;
}

}  // namespace

const std::vector<std::string>& benchMethodNames() {
  static const std::vector<std::string> names = [] {
    // The rendering variants of light-traced VPLs and rejection first, in the places they have always had (a
    // method's chart colour is its place), then every other generation variant.
    std::vector<std::string> n = {"vpl", "clamp", "ssbc", "vsl", "reject", "vpl-kk"};
    for (const GenerationVariant& v : generationVariants())
      if (std::find(n.begin(), n.end(), v.name) == n.end()) n.push_back(v.name);
    // The media methods (renderer/offline/render_methods.h), rows only on scenes with participating media.
    for (const RenderMethod& m : renderMethods())
      if (m.forMedia) n.push_back(toString(m.id));
    // Local virtual lights, rows on scenes without media.
    n.push_back(toString(Method::Lvl));
    // The many-light methods for large VPL counts (surfaces only).
    n.push_back(toString(Method::Lightcuts));
    n.push_back(toString(Method::Mrcs));
    return n;
  }();
  return names;
}

unsigned benchMethodColourRgb(const std::string& method) {
  const int index = benchMethodIndex(method);
  return chartColourRgb(index < 0 ? 0u : static_cast<std::size_t>(index));
}

const std::vector<std::string>& benchCsvHeader() {
  static const std::vector<std::string> header = {
      "scene",         "method",     "backend",      "components", "width",     "height",          "seed",
      "vpls",          "bounces",    "clamp_b",      "vsl_r",      "rejection", "epsilon",         "interleave",
      "ssbc",          "shadow_map", "spp",          "ref_spp",    "gen_ms",    "render_ms",       "time_ms",
      "relmse",        "rmse",       "energy_ratio", "nonfinite",  "negative",  "acceptance_rate", "acceptance_spread",
      "vpls_accepted", "image_id"};
  return header;
}

std::size_t benchCsvKeyColumns() {
  return 18;
}

std::vector<BenchCase> benchCases(const Scene& scene, const BenchConfig& config) {
  const float diag = std::max(scene.bounds.diagonal(), 1e-3f);
  Settings base;
  base.width = config.width;
  base.height = config.height;
  base.seed = config.seed;
  base.threads = config.threads;
  base.components = config.components;
  base.samplesPerPixel = config.cpuSpp;

  const std::vector<int> counts = config.quick ? std::vector<int>{32, 128} : std::vector<int>{64, 256, 1024};
  const int n = config.quick ? 64 : 256;
  std::vector<float> bounds;
  for (float f : config.quick ? std::vector<float>{0.15f, 0.05f} : std::vector<float>{0.3f, 0.15f, 0.075f, 0.04f})
    bounds.push_back(round2(1.0f / (f * diag * f * diag)));
  std::vector<float> radii;
  for (float f : config.quick ? std::vector<float>{0.03f} : std::vector<float>{0.01f, 0.03f, 0.1f})
    radii.push_back(round2(f * diag));
  const std::vector<float> epsilons =
      config.quick ? std::vector<float>{0.0f, 0.2f, 1.0f} : std::vector<float>{0.0f, 0.05f, 0.2f, 1.0f};

  std::vector<BenchCase> cases;
  auto add = [&](const std::string& method, Backend backend, auto&& edit) {
    if (!wanted(config, method) || (backend == Backend::Gl && !config.gl)) return;
    BenchCase c{method, backend, base};
    c.settings.vplCount = n;
    edit(c.settings);
    cases.push_back(c);
  };
  for (Backend be : {Backend::Cpu, Backend::Gl}) {
    for (int count : counts) add("vpl", be, [&](Settings& s) { s.vplCount = count; });
    for (float b : bounds) add("clamp", be, [&](Settings& s) { s.clampBound = b; });
    for (float r : radii) add("vsl", be, [&](Settings& s) { s.vslRadius = r; });
    for (float e : epsilons)
      add("reject", be, [&](Settings& s) {
        s.rejection = true;
        s.rejectionEpsilon = e;
      });
    // The other generation methods at the VPL counts of plain light tracing, so their rows compare at equal N.
    for (const GenerationVariant& v : generationVariants()) {
      if (v.generation == VplGeneration::Light) continue;
      for (int count : counts)
        add(v.name, be, [&](Settings& s) {
          applyGenerationVariant(v, s);
          s.vplCount = count;
        });
    }
  }
  // The GL preview's own levers: interleaving (k x k fewer evaluations) and the shadow-map resolution.
  for (int k : config.quick ? std::vector<int>{4} : std::vector<int>{2, 4})
    add("vpl", Backend::Gl, [&](Settings& s) {
      s.vplCount = counts.back();
      s.interleave = k;
    });
  add("vpl", Backend::Gl, [&](Settings& s) { s.shadowMapSize = 64; });
  for (float b : bounds)
    add("ssbc", Backend::Gl, [&](Settings& s) {
      s.clampBound = b;
      s.ssbcSteps = 2;
    });
  add("ssbc", Backend::Gl, [&](Settings& s) {
    s.clampBound = bounds[bounds.size() / 2];
    s.ssbcSteps = 1;
  });
  for (float b : bounds) add("vpl-kk", Backend::Cpu, [&](Settings& s) { s.clampBound = b; });
  // Local virtual lights at Kollig-Keller's bounds (surfaces only).
  if (!scene.hasMedia())
    for (float b : bounds) add("lvl", Backend::Cpu, [&](Settings& s) { s.clampBound = b; });
  // Lightcuts (1 %) and matrix row-column sampling (300 rows, 900 clusters) at 4x and 16x the largest plain VPL count,
  // at the middle bound: what the VPL count they afford buys at their cost (surfaces only; docs/methods.md).
  if (!scene.hasMedia())
    for (int factor : config.quick ? std::vector<int>{4} : std::vector<int>{4, 16})
      for (const char* m : {"lightcuts", "mrcs"})
        add(m, Backend::Cpu, [&](Settings& s) {
          s.vplCount = counts.back() * factor;
          s.clampBound = bounds[bounds.size() / 2];
        });
  if (scene.hasMedia()) {
    // The media methods (docs/methods.md, "Participating media"): the approximate compensation at the same bounds as
    // Kollig-Keller, ray lights at the VPL counts of plain VPLs, beams at those counts per pass.
    for (float b : bounds) add("vpl-abc", Backend::Cpu, [&](Settings& s) { s.clampBound = b; });
    for (int count : counts) add("vrl", Backend::Cpu, [&](Settings& s) { s.vplCount = count; });
    for (int count : counts) add("vbl", Backend::Cpu, [&](Settings& s) { s.vplCount = count; });
  }
  return cases;
}

BenchOutcome runBench(const std::vector<std::string>& scenePaths, const BenchConfig& config) {
  fs::create_directories(config.outDir);
  BenchOutcome outcome;
  CsvLog log(config.outDir + "/bench.csv", benchCsvHeader(), benchCsvKeyColumns());
  PreviewBench gl(config.glBackend);
  std::vector<std::string> names;
  std::size_t run = 0;  // counts every scene's cases: the shard split

  for (const std::string& path : scenePaths) {
    const std::string name = sceneStem(path);
    names.push_back(name);
    OfflineScene setup(loadSweepScene(config.loadScene, path));
    std::vector<BenchCase> cases = benchCases(setup.scene(), config);
    const std::size_t firstRun = run;
    run += cases.size();
    auto inShard = [&](std::size_t i) {
      return (firstRun + i) % static_cast<std::size_t>(config.shardCount) ==
             static_cast<std::size_t>(config.shardIndex);
    };
    bool anyInShard = false;
    for (std::size_t i = 0; i < cases.size(); ++i) anyInShard = anyInShard || inShard(i);
    if (!anyInShard) continue;

    Settings refSettings;
    refSettings.width = config.width;
    refSettings.height = config.height;
    refSettings.samplesPerPixel = config.referenceSpp;
    refSettings.components = config.components;
    refSettings.seed = config.seed;
    refSettings.threads = config.threads;
    say(config, name + ": reference " + std::to_string(config.width) + "x" + std::to_string(config.height) + ", " +
                    std::to_string(config.referenceSpp) + " spp, " + toString(config.components));
    bool cached = false;
    MeasuredImage ref = cachedReference(setup, name, refSettings, config.outDir + "/references", &cached);
    say(config,
        name + ": reference " +
            (cached ? std::string("reused from the cache") : "rendered in " + fmt(ref.renderMs / 1000.0) + " s"));
    // The cached reference's name holds a hash of the loaded scene (staging and lights sidecar included): a reference
    // rendered anew means the rows already logged for this scene name may measure another scene, so they are redone.
    if (!cached)
      if (std::size_t dropped = log.removeRows("scene", name))
        say(config, name + ": " + std::to_string(dropped) +
                        " row(s) in bench.csv were measured against another reference of this scene and are redone");
    const float exposure = autoExposure(ref.image);
    const std::string imageDir = config.outDir + "/images/" + name;
    if (config.writeImages) {
      fs::create_directories(imageDir);
      writeImage(imageDir + "/reference.png", ref.image, exposure);
    }

    std::map<std::string, VplSet> vplCache;
    for (std::size_t i = 0; i < cases.size(); ++i) {
      if (!inShard(i)) continue;
      const BenchCase& c = cases[i];
      std::vector<std::string> key = keyOf(name, c, config);
      std::string head = name + " [" + std::to_string(i + 1) + "/" + std::to_string(cases.size()) + "] " + c.method +
                         " (" + toString(c.backend) + ")";
      if (log.contains(key)) {
        ++outcome.rowsReused;
        say(config, head + ": already in bench.csv, skipped");
        continue;
      }
      if (c.backend == Backend::Gl && !gl.available()) {
        if (outcome.glNote.empty()) {
          outcome.glNote = "GL rows skipped: " + gl.error();
          say(config, outcome.glNote);
        }
        continue;
      }
      std::string gk = generationKey(c.settings);
      auto it = vplCache.find(gk);
      if (it == vplCache.end()) it = vplCache.emplace(gk, generateVpls(setup, c.settings)).first;
      const VplSet& vpls = it->second;

      MeasuredImage m;
      if (c.backend == Backend::Cpu) {
        // Rows named after a render method use it; the others (clamp, reject, the generation variants) are VPL
        // renders of their own VPLs and bound.
        Method method = Method::Vpl;
        if (!parseMethod(c.method, method)) method = Method::Vpl;
        m = renderCpu(setup, method, vpls, c.settings);
      } else {
        m = gl.render(setup.scene(), vpls, c.settings, setup.scene().camera);
      }
      ImageMetrics metrics = compareImages(m.image, ref.image);
      // A short stable file name for a run's images.
      std::string id = fnv1a64Hex([&] {
        std::string k;
        for (const std::string& f : key) k += f + "|";
        return k;
      }());
      std::vector<std::string> row = key;
      for (const std::string& v :
           {fmt(m.generationMs), fmt(m.renderMs), fmt(m.totalMs()), fmt(metrics.relMse), fmt(metrics.rmse),
            fmt(metrics.energyRatioOverall), std::to_string(metrics.nonFinitePixels),
            std::to_string(metrics.negativePixels), fmt(m.vplStats.acceptanceRate), fmt(m.vplStats.acceptanceSpread),
            std::to_string(m.vplStats.accepted), id})
        row.push_back(v);
      log.append(row);
      ++outcome.rowsMeasured;
      if (config.writeImages) {
        writeImage(imageDir + "/" + id + ".png", m.image, exposure);
        HeatmapOptions h;
        h.title = "relative error (I-R)^2/(R^2+0.01)";
        writeHeatmap(imageDir + "/" + id + "-err.png", relativeErrorImage(m.image, ref.image), h);
      }
      char line[256];
      std::snprintf(line, sizeof line, ": %s  time %.1f ms (gen %.1f)  relMSE %.4g  energy %.3f",
                    describeRow(log.rows().back()).c_str(), m.totalMs(), m.generationMs, metrics.relMse,
                    metrics.energyRatioOverall);
      say(config, head + line);
    }
  }
  if (config.shardCount > 1) {
    // A shard's rows are a part of the sweep: its report is the merged one.
    outcome.csvPath = log.path();
    return outcome;
  }
  BenchOutcome report = writeBenchReport(names, config);
  report.rowsMeasured = outcome.rowsMeasured;
  report.rowsReused = outcome.rowsReused;
  report.glNote = outcome.glNote;
  return report;
}

BenchOutcome mergeBench(const std::vector<std::string>& shardDirs, BenchConfig config) {
  fs::create_directories(config.outDir);
  CsvLog log(config.outDir + "/bench.csv", benchCsvHeader(), benchCsvKeyColumns());
  const std::vector<std::string>& header = benchCsvHeader();
  BenchOutcome outcome;
  std::vector<std::vector<std::string>> added;
  for (const std::string& dir : shardDirs) {
    std::vector<std::string> found;
    std::vector<CsvRow> rows = readCsv(dir + "/bench.csv", &found);
    if (found != header) throw CsvError(dir + "/bench.csv: the header differs from this version's columns");
    for (const CsvRow& r : rows) {
      std::vector<std::string> values;
      for (const std::string& column : header) values.push_back(r.at(column));
      std::vector<std::string> key(values.begin(), values.begin() + static_cast<long>(benchCsvKeyColumns()));
      if (log.contains(key)) {
        ++outcome.rowsReused;
        continue;
      }
      log.append(values, /*save=*/false);
      ++outcome.rowsMeasured;
    }
    // The per-run images the report links to, under the same names.
    if (fs::is_directory(dir + "/images"))
      fs::copy(dir + "/images", config.outDir + "/images",
               fs::copy_options::recursive | fs::copy_options::skip_existing);
  }
  log.save();
  std::vector<std::string> names;
  for (const CsvRow& r : log.rows()) {
    if (std::find(names.begin(), names.end(), r.at("scene")) == names.end()) names.push_back(r.at("scene"));
    Components c;
    if (!parseComponents(r.at("components"), c))
      throw CsvError(log.path() + ": unknown components '" + r.at("components") + "'");
    if (&r != &log.rows().front() && c != config.components)
      throw CsvError(log.path() + ": the runs compare different components; merge shards of one sweep");
    config.components = c;
  }
  BenchOutcome report = writeBenchReport(names, config);
  report.rowsMeasured = outcome.rowsMeasured;
  report.rowsReused = outcome.rowsReused;
  return report;
}

BenchOutcome writeBenchReport(const std::vector<std::string>& sceneNames, const BenchConfig& config) {
  BenchOutcome outcome;
  outcome.csvPath = config.outDir + "/bench.csv";
  outcome.reportPath = config.outDir + "/report.md";
  std::vector<CsvRow> all = readCsv(outcome.csvPath);
  const std::string chartDir = config.outDir + "/charts";
  fs::create_directories(chartDir);

  std::ostringstream md;
  md << "# vplab bench report\n\n";
  md << "Each run is one method on one backend with one set of parameters, measured against a path-traced "
        "reference of the same size.\n"
     << "- **Compared**: the `" << toString(config.components) << "` component"
     << (config.components == Components::Indirect
             ? " (light after two or more reflections: the part VPLs approximate; direct light is exact in the CPU "
               "pass and shadow-mapped in GL, so it is left out of the comparison)"
             : " (the full image)")
     << ".\n"
     << "- **Time** = VPL generation (pilots, importance, resampling or chains included) + render. CPU: wall time of "
        "the exact VPL render "
        "on "
        "all threads. GL: wall time of a whole preview frame from scratch up to glFinish (VPL shadow maps included; "
        "the faster of two)"
     << (config.components == Components::Indirect
             ? ", with the direct light, which is not compared, reduced to one shadow-mapped sample"
             : "")
     << ".\n"
     << "- **Error**: relMSE = mean((I-R)^2/(R^2+0.01)), energy ratio = mean(I)/mean(R) (a clamp shows as < 1).\n"
     << "- Data: [bench.csv](bench.csv). Chart points on the dashed line are Pareto-optimal: no other run is both "
        "faster and more accurate.\n\n";

  for (const std::string& scene : sceneNames) {
    std::vector<const CsvRow*> rows;
    for (const CsvRow& r : all)
      if (r.at("scene") == scene && std::stoi(r.at("width")) == config.width &&
          std::stoi(r.at("height")) == config.height && r.at("components") == toString(config.components))
        rows.push_back(&r);
    md << "## " << scene << "\n\n";
    if (rows.empty()) {
      md << "No runs measured.\n\n";
      continue;
    }
    auto groups = groupRows(rows);

    // Time vs relMSE with the Pareto front over every run of the scene.
    ChartSpec pareto;
    pareto.title = scene + ": time vs error (" + std::string(toString(config.components)) + ")";
    pareto.xLabel = "time per image [ms]";
    pareto.yLabel = "relMSE";
    pareto.logX = pareto.logY = true;
    std::vector<glm::dvec2> allPts;
    std::vector<const CsvRow*> allRows;
    for (const auto& [k, g] : groups)
      for (const CsvRow* r : g) {
        allPts.push_back({toDouble(r->at("time_ms")), toDouble(r->at("relmse"))});
        allRows.push_back(r);
      }
    std::vector<std::size_t> front = paretoFront(allPts);
    std::set<const CsvRow*> onFront;
    for (std::size_t i : front) {
      pareto.front.push_back(allPts[i]);
      onFront.insert(allRows[i]);
    }
    for (const auto& [k, g] : groups) {
      ChartSeries s = methodSeries(k.method, k.backend);
      s.connect = false;
      for (const CsvRow* r : g) {
        s.points.push_back({toDouble(r->at("time_ms")), toDouble(r->at("relmse"))});
        s.labels.push_back(onFront.count(r) ? describeRow(*r) : "");
      }
      pareto.series.push_back(std::move(s));
    }
    std::string paretoFile = scene + "-pareto.svg";
    writeSvgChart(chartDir + "/" + paretoFile, pareto);
    outcome.charts.push_back(chartDir + "/" + paretoFile);
    md << "![time vs relMSE](charts/" << paretoFile << ")\n\n";

    // Energy ratio vs the clamp bound b: what the clamp removes and what compensation gives back.
    ChartSpec energy;
    energy.title = scene + ": energy ratio vs clamp bound b";
    energy.xLabel = "clamp bound b [1/m^2]";
    energy.yLabel = "energy ratio mean(I)/mean(R)";
    energy.logX = true;
    for (const auto& [k, g] : groups) {
      ChartSeries s = methodSeries(k.method, k.backend);
      std::vector<std::pair<double, double>> pts;
      for (const CsvRow* r : g) {
        double b = toDouble(r->at("clamp_b"));
        if (std::isfinite(b) && r->at("interleave") == "1") pts.push_back({b, toDouble(r->at("energy_ratio"))});
      }
      if (pts.empty()) continue;
      std::sort(pts.begin(), pts.end());
      for (auto [x, y] : pts) s.points.push_back({x, y});
      energy.series.push_back(std::move(s));
    }
    if (!energy.series.empty()) {
      std::string file = scene + "-energy-vs-b.svg";
      writeSvgChart(chartDir + "/" + file, energy);
      outcome.charts.push_back(chartDir + "/" + file);
      md << "![energy ratio vs b](charts/" << file << ")\n\n";
    }

    // Rejection: acceptance rate and relMSE vs epsilon.
    ChartSpec acc, err;
    acc.title = scene + ": rejection acceptance rate vs epsilon";
    acc.xLabel = "epsilon";
    acc.yLabel = "acceptance rate";
    err.title = scene + ": relMSE vs rejection epsilon";
    err.xLabel = "epsilon";
    err.yLabel = "relMSE";
    err.logY = true;
    for (const auto& [k, g] : groups) {
      if (k.method != "reject") continue;
      ChartSeries a = methodSeries(k.method, k.backend), e = a;
      std::vector<const CsvRow*> sorted = g;
      std::sort(sorted.begin(), sorted.end(), [](const CsvRow* x, const CsvRow* y) {
        return toDouble(x->at("epsilon")) < toDouble(y->at("epsilon"));
      });
      for (const CsvRow* r : sorted) {
        a.points.push_back({toDouble(r->at("epsilon")), toDouble(r->at("acceptance_rate"))});
        e.points.push_back({toDouble(r->at("epsilon")), toDouble(r->at("relmse"))});
      }
      // Acceptance depends only on the VPLs, shared by both backends: one series is enough.
      if (acc.series.empty()) acc.series.push_back(std::move(a));
      err.series.push_back(std::move(e));
    }
    if (!acc.series.empty()) {
      for (auto [spec, file] :
           {std::pair{&acc, scene + "-epsilon-acceptance.svg"}, std::pair{&err, scene + "-epsilon-relmse.svg"}}) {
        writeSvgChart(chartDir + "/" + file, *spec);
        outcome.charts.push_back(chartDir + "/" + file);
        md << "![" << spec->title << "](charts/" << file << ")\n\n";
      }
    }

    md << "### Pareto-optimal runs\n\n| method | backend | parameters | time [ms] | relMSE | energy ratio |\n"
          "|---|---|---|---:|---:|---:|\n";
    for (std::size_t i : front) {
      const CsvRow& r = *allRows[i];
      md << "| " << r.at("method") << " | " << r.at("backend") << " | " << describeRow(r) << " | " << r.at("time_ms")
         << " | " << r.at("relmse") << " | " << r.at("energy_ratio") << " |\n";
    }
    md << "\n### Best run of each method (lowest relMSE), with images\n\n"
          "| method | backend | parameters | time [ms] | relMSE | energy | image | reference | relative error |\n"
          "|---|---|---|---:|---:|---:|---|---|---|\n";
    for (const auto& [k, g] : groups) {
      const CsvRow* best = *std::min_element(g.begin(), g.end(), [](const CsvRow* a, const CsvRow* b) {
        return toDouble(a->at("relmse")) < toDouble(b->at("relmse"));
      });
      std::string base = "images/" + scene + "/";
      std::string id = best->at("image_id");
      auto rel = [&](const std::string& f) { return fs::exists(config.outDir + "/" + f) ? "![](" + f + ")" : "-"; };
      md << "| " << k.method << " | " << k.backend << " | " << describeRow(*best) << " | " << best->at("time_ms")
         << " | " << best->at("relmse") << " | " << best->at("energy_ratio") << " | " << rel(base + id + ".png")
         << " | " << rel(base + "reference.png") << " | " << rel(base + id + "-err.png") << " |\n";
    }
    md << "\n### All runs\n\n| method | backend | parameters | gen [ms] | render [ms] | relMSE | RMSE | energy | "
          "acceptance | non-finite | negative |\n|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& [k, g] : groups)
      for (const CsvRow* r : g)
        md << "| " << k.method << " | " << k.backend << " | " << describeRow(*r) << " | " << r->at("gen_ms") << " | "
           << r->at("render_ms") << " | " << r->at("relmse") << " | " << r->at("rmse") << " | " << r->at("energy_ratio")
           << " | " << r->at("acceptance_rate") << spreadOf(*r) << " | " << r->at("nonfinite") << " | "
           << r->at("negative") << " |\n";
    md << "\n";
  }
  writeFileAtomically(outcome.reportPath, md.str());
  return outcome;
}

}  // namespace vplab
