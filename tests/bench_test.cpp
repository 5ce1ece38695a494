// The bench sweep and its outputs: the SVG writer (well-formed XML checked by a strict parser, one series per
// method, the Pareto front), the resumable CSV log, and a tiny sweep on the Cornell box (expected columns, finite
// values, restart skips measured rows). GlBench runs the GL variants and needs a context.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "evaluation/csv_log.h"
#include "evaluation/svg_chart.h"
#include "evaluation/sweep.h"
#include "renderer/vpl/generation_methods.h"
#include "tests/xml_check.h"
#include "tests/test_tmp.h"

namespace vplab {
namespace {

namespace fs = std::filesystem;

std::string tmpDir(const std::string& name) {
  std::string dir = vplab::test::tmpDir() + "/" + name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string readText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string cornellBox() {
  return std::string(VPLAB_TEST_ASSETS) + "/scenes/cornell-box.gltf";
}

BenchConfig tinyConfig(const std::string& dir) {
  BenchConfig c;
  c.outDir = dir;
  c.width = c.height = 64;
  c.quick = true;
  c.referenceSpp = 16;
  c.cpuSpp = 1;
  c.gl = false;
  return c;
}

// Parses every chart and checks that the series are exactly the (method, backend) pairs of the CSV rows.
void expectChartsMatchCsv(const BenchOutcome& out) {
  std::vector<CsvRow> rows = readCsv(out.csvPath);
  std::set<std::string> expectedSeries;
  for (const CsvRow& r : rows) expectedSeries.insert(r.at("method") + " (" + r.at("backend") + ")");
  ASSERT_FALSE(out.charts.empty());
  for (const std::string& chart : out.charts) {
    SCOPED_TRACE(chart);
    XmlElement svg;
    ASSERT_NO_THROW(svg = parseXml(readText(chart)));
    EXPECT_EQ(svg.name, "svg");
    auto series = svg.findAll("g", "class", "series");
    std::set<std::string> names;
    for (const XmlElement* s : series) names.insert(s->attributes.at("data-name"));
    EXPECT_EQ(names.size(), series.size()) << "a method appears twice";
    EXPECT_EQ(svg.findAll("g", "class", "legend-entry").size() - svg.findAll("g", "class", "pareto-front").size(),
              series.size());
    for (const std::string& n : names) EXPECT_TRUE(expectedSeries.count(n)) << n;
    if (chart.find("pareto") != std::string::npos) {
      EXPECT_EQ(names, expectedSeries);
    }
  }
}

TEST(BenchSvg, ChartIsWellFormedWithOneGroupPerSeries) {
  ChartSpec spec;
  spec.title = "a < b & \"c\"";  // must be escaped
  spec.logX = spec.logY = true;
  spec.series.push_back({"vpl (cpu)", {{1, 0.1}, {10, 0.01}}, {"N=1", ""}, true});
  spec.series.push_back({"clamp (gl)", {{2, 0.05}, {-1, 0.2}, {NAN, 1}}, {}, false});  // two undrawable points
  spec.front = {{1, 0.1}, {10, 0.01}};
  XmlElement svg = parseXml(renderSvgChart(spec));
  EXPECT_EQ(svg.findAll("g", "class", "series").size(), 2u);
  EXPECT_EQ(svg.findAll("g", "class", "pareto-front").size(), 1u);
  EXPECT_EQ(svg.findAll("title")[0]->text, spec.title);
  // The two undrawable points are reported, not silently dropped.
  auto notes = svg.findAll("text", "class", "note");
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0]->text.find("2 point"), std::string::npos);
  // One marker per drawable point: the clamp series keeps only (2, 0.05).
  EXPECT_EQ(svg.findAll("g", "class", "series")[1]->children.size(), 1u);
}

TEST(BenchSvg, SeriesKeepTheirMethodsColourAndBackendsShape) {
  // A method's colour does not depend on which other series a chart happens to have.
  ChartSpec spec;
  spec.logX = spec.logY = true;
  ChartSeries vsl{"vsl (gl)", {{2, 0.05}}, {}, false};
  vsl.colour = benchMethodIndex("vsl");
  vsl.shape = benchBackendShape(true);
  spec.series.push_back(vsl);
  XmlElement svg = parseXml(renderSvgChart(spec));
  const XmlElement* series = svg.findAll("g", "class", "series").at(0);
  ASSERT_EQ(series->children.size(), 1u);
  EXPECT_EQ(series->children[0].name, "rect");  // the GL marker: a square
  char colour[8];
  std::snprintf(colour, sizeof colour, "#%06x", chartColourRgb(static_cast<std::size_t>(benchMethodIndex("vsl"))));
  EXPECT_EQ(series->children[0].attributes.at("fill"), colour);
  EXPECT_NE(chartColourRgb(0), chartColourRgb(3));
  EXPECT_EQ(benchMethodIndex("no such method"), -1);
  EXPECT_EQ(axisTickLabel(0.002), "0.002");
  EXPECT_EQ(axisTickLabel(1e-4), "1e-04");
}

// Every generation variant is a bench method with a colour of its own (its rows, its chart series and the editor's
// VPL overlay ring share it).
TEST(BenchSvg, EveryGenerationVariantIsABenchMethodWithItsOwnColour) {
  std::set<unsigned> colours;
  for (const std::string& m : benchMethodNames()) EXPECT_TRUE(colours.insert(benchMethodColourRgb(m)).second) << m;
  for (const GenerationVariant& v : generationVariants()) {
    ASSERT_GE(benchMethodIndex(v.name), 0) << v.name;
    EXPECT_EQ(benchMethodColourRgb(v.name), chartColourRgb(static_cast<std::size_t>(benchMethodIndex(v.name))));
  }
}

TEST(BenchSvg, StrictParserRejectsMalformedXml) {
  EXPECT_THROW(parseXml("<svg><g></svg>"), XmlError);
  EXPECT_THROW(parseXml("<svg a=\"1\" a=\"2\"/>"), XmlError);
  EXPECT_THROW(parseXml("<svg>&nbsp;</svg>"), XmlError);
  EXPECT_THROW(parseXml("<svg/><svg/>"), XmlError);
  EXPECT_THROW(parseXml("<svg a=1/>"), XmlError);
  EXPECT_NO_THROW(parseXml("<?xml version=\"1.0\"?>\n<!-- c --><svg a='&lt;'><g/>t&amp;&#65;</svg>\n"));
  EXPECT_EQ(parseXml("<svg>t&amp;&#65;</svg>").text, "t&A");
}

TEST(BenchSvg, ParetoFrontKeepsOnlyUndominatedPoints) {
  std::vector<glm::dvec2> pts = {{1, 5}, {2, 3}, {3, 4}, {4, 1}, {2, 3}, {5, 1}, {0.5, 9}, {NAN, 0}};
  std::vector<std::size_t> front = paretoFront(pts);
  EXPECT_EQ(front, (std::vector<std::size_t>{6, 0, 1, 3}));
}

TEST(BenchSvg, AxisTicksAreNiceAndCoverTheRange) {
  auto expectTicks = [](const std::vector<double>& got, const std::vector<double>& want) {
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t i = 0; i < got.size(); ++i) EXPECT_NEAR(got[i], want[i], 1e-12 * std::max(1.0, want[i]));
  };
  expectTicks(axisTicks(0.0, 1.0, false, 5), {0.0, 0.2, 0.4, 0.6, 0.8, 1.0});
  expectTicks(axisTicks(-3.0, 14.0, false, 4), {0.0, 5.0, 10.0});
  // Five decades: powers of ten only. Fewer than three: 2 and 5 in between too.
  expectTicks(axisTicks(0.003, 40.0, true), {0.01, 0.1, 1.0, 10.0});
  expectTicks(axisTicks(1.5, 30.0, true), {2.0, 5.0, 10.0, 20.0});
}

TEST(BenchCsv, LogResumesAndDropsACutOffRow) {
  std::string dir = tmpDir("bench_csv");
  std::string path = dir + "/log.csv";
  {
    CsvLog log(path, {"a", "b", "value"}, 2);
    log.append({"x", "1", "0.5"});
    log.append({"y,z", "2", "\"q\""});
  }
  {
    std::ofstream cut(path, std::ios::app);
    cut << "w,3";  // an interrupted write: fewer fields than the header, no newline
  }
  CsvLog again(path, {"a", "b", "value"}, 2);
  EXPECT_EQ(again.rows().size(), 2u);
  EXPECT_TRUE(again.contains({"x", "1"}));
  EXPECT_TRUE(again.contains({"y,z", "2"}));
  EXPECT_FALSE(again.contains({"w", "3"}));
  EXPECT_EQ(again.rows()[1].at("value"), "\"q\"");
  again.append({"w", "3", "1"});
  EXPECT_EQ(readCsv(path).size(), 3u);
  EXPECT_THROW(CsvLog(path, {"a", "other"}, 1), CsvError);
}

TEST(BenchSweep, TinySweepWritesFiniteRowsChartsAndResumes) {
  std::string dir = tmpDir("bench_sweep");
  BenchConfig config = tinyConfig(dir);
  config.methods = {"vpl", "clamp", "reject", "bidirectional", "metropolis"};
  BenchOutcome out = runBench({cornellBox()}, config);

  std::vector<std::string> header;
  std::vector<CsvRow> rows = readCsv(out.csvPath, &header);
  EXPECT_EQ(header, benchCsvHeader());
  for (const char* col :
       {"scene", "method", "backend", "vpls", "clamp_b", "vsl_r", "epsilon", "interleave", "ssbc", "shadow_map",
        "time_ms", "relmse", "rmse", "energy_ratio", "nonfinite", "negative", "acceptance_rate"})
    EXPECT_NE(std::find(header.begin(), header.end(), col), header.end()) << col;
  // quick: 2 N values, 2 clamp bounds, 3 epsilons, and the 2 N values of each other generation method on the CPU.
  ASSERT_EQ(rows.size(), 11u);
  EXPECT_EQ(out.rowsMeasured, 11u);
  for (const CsvRow& r : rows) {
    for (const char* col : {"time_ms", "relmse", "rmse", "energy_ratio", "acceptance_rate"}) {
      double v = std::stod(r.at(col));
      EXPECT_TRUE(std::isfinite(v) && v >= 0.0) << col << " = " << r.at(col);
    }
    EXPECT_EQ(r.at("nonfinite"), "0");
    EXPECT_EQ(r.at("negative"), "0");
    EXPECT_GT(std::stod(r.at("relmse")), 0.0);
    if (r.at("method") == "reject") {
      EXPECT_LE(std::stod(r.at("acceptance_rate")), 1.0);
      // The pilot predicts a spread wherever something can be rejected.
      if (std::stod(r.at("epsilon")) < 1.0) {
        EXPECT_GT(std::stod(r.at("acceptance_spread")), 0.0) << r.at("epsilon");
      }
    }
    if (r.at("method") == "bidirectional" || r.at("method") == "metropolis") {
      // Compared at the VPL counts of plain light tracing: the kept count is the requested one, give or take.
      EXPECT_NEAR(std::stod(r.at("vpls_accepted")) / std::stod(r.at("vpls")), 1.0, 0.3) << r.at("method");
    }
    EXPECT_TRUE(fs::exists(dir + "/images/cornell-box/" + r.at("image_id") + "-err.png"));
  }
  expectChartsMatchCsv(out);
  EXPECT_EQ(out.charts.size(), 4u);  // pareto, energy vs b, acceptance and relMSE vs epsilon
  std::string report = readText(out.reportPath);
  EXPECT_NE(report.find("charts/cornell-box-pareto.svg"), std::string::npos);
  EXPECT_NE(report.find("images/cornell-box/reference.png"), std::string::npos);

  // The same output folder again: the reference comes from the cache and no run is measured twice.
  BenchOutcome again = runBench({cornellBox()}, config);
  EXPECT_EQ(again.rowsMeasured, 0u);
  EXPECT_EQ(again.rowsReused, 11u);
  EXPECT_EQ(readCsv(out.csvPath).size(), 11u);
}

TEST(BenchSweep, CasesScaleWithTheSceneAndHonourTheMethodList) {
  Scene small;
  small.bounds.extend(glm::vec3(0.0f));
  small.bounds.extend(glm::vec3(1.0f, 0.0f, 0.0f));
  Scene large = small;
  large.bounds.extend(glm::vec3(10.0f, 0.0f, 0.0f));
  BenchConfig c;
  c.methods = {"clamp"};
  c.gl = false;
  auto a = benchCases(small, c), b = benchCases(large, c);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_FALSE(a.empty());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].method, "clamp");
    EXPECT_EQ(a[i].backend, Backend::Cpu);
    // b = 1 / (f D)^2: a scene ten times larger gets bounds about a hundred times smaller.
    EXPECT_NEAR(a[i].settings.clampBound / b[i].settings.clampBound, 100.0, 5.0);
  }
}

TEST(GlBench, GlVariantsAreMeasuredAndCharted) {
  std::string dir = tmpDir("gl_bench_sweep");
  BenchConfig config = tinyConfig(dir);
  config.gl = true;
  config.methods = {"ssbc", "vpl"};
  BenchOutcome out = runBench({cornellBox()}, config);
  ASSERT_TRUE(out.glNote.empty()) << out.glNote;
  std::vector<CsvRow> rows = readCsv(out.csvPath);
  std::size_t gl = 0;
  for (const CsvRow& r : rows) {
    gl += r.at("backend") == "gl";
    EXPECT_TRUE(std::isfinite(std::stod(r.at("relmse")))) << r.at("method");
    EXPECT_GT(std::stod(r.at("time_ms")), 0.0);
    EXPECT_EQ(r.at("nonfinite"), "0");
  }
  // quick: vpl at 2 N + interleaved + small shadow maps, ssbc at 2 bounds + 1 step.
  EXPECT_EQ(gl, 7u);
  expectChartsMatchCsv(out);
}

}  // namespace
}  // namespace vplab
