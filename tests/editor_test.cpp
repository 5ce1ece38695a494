// The editor: its pure logic (scripts, camera, chart, presets) and a scripted run of `vplab edit` under Xvfb whose
// view is compared with the headless preview of the same settings and camera.

#include "evaluation/svg_chart.h"
#include "evaluation/sweep.h"
#include "renderer/core/sampling.h"
#include "renderer/gl/context.h"
#include "renderer/gl/preview_renderer.h"
#include "renderer/image/image_io.h"
#include "renderer/image/metrics.h"
#include "renderer/image/tonemap.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/settings_json.h"
#include "renderer/vpl/generation_methods.h"
#include "renderer/vpl/vpl_generation.h"
#include "tests/test_scenes.h"
#include "tests/test_tmp.h"

#ifdef VPLAB_HAVE_EDITOR
#include "ui/camera_controller.h"
#include "ui/change_timer.h"
#include "ui/chart.h"
#include "ui/editor.h"
#include "ui/offline_job.h"
#include "ui/panels.h"
#include "ui/presets.h"
#include "ui/script.h"
#endif

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

namespace vplab {
namespace {

#ifdef VPLAB_HAVE_EDITOR

TEST(EditorScript, ParsesCommandsAndSkipsComments) {
  auto commands = ui::parseScript("# a comment\nset clampBound 0.5  # trailing\n\norbit 10 -5\npreset Corner splotches "
                                  "(no bound)\nlight 0 move 0 0.1 0\nexpect-no-vpl-regeneration\n",
                                  "s.txt");
  ASSERT_EQ(commands.size(), 5u);
  EXPECT_EQ(commands[0].verb, "set");
  EXPECT_EQ(commands[0].args, (std::vector<std::string>{"clampBound", "0.5"}));
  EXPECT_EQ(commands[0].line, 2);
  EXPECT_EQ(commands[1].line, 4);
  EXPECT_EQ(commands[2].args, (std::vector<std::string>{"Corner splotches (no bound)"}));
  EXPECT_EQ(commands[3].args.size(), 5u);
}

TEST(EditorScript, ErrorsNameTheLine) {
  auto expectError = [](const std::string& text, const std::string& fragment) {
    try {
      ui::parseScript(text, "s.txt");
      FAIL() << "no error for: " << text;
    } catch (const ui::ScriptError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  expectError("frames 2\nfly 1 2\n", "s.txt:2: unknown command 'fly'");
  expectError("orbit 10\n", "s.txt:1:");
  expectError("orbit ten 5\n", "'ten' is not a number");
  expectError("light 0 spin 3\n", "light <i> move");
  expectError("offline fast\n", "reference");
}

TEST(EditorCamera, StartsAtTheSceneCameraAndOrbitsAroundTheTarget) {
  Camera cam;
  cam.position = {0.278f, 0.273f, -0.8f};
  cam.forward = {0.0f, 0.0f, 1.0f};
  cam.up = {0.0f, 1.0f, 0.0f};
  ui::CameraController c(cam, 1.0f, 1.0f);
  Camera start = c.camera();
  EXPECT_NEAR(glm::length(start.position - cam.position), 0.0f, 1e-5f);
  EXPECT_NEAR(glm::dot(start.forward, cam.forward), 1.0f, 1e-6f);
  glm::vec3 target = c.target();
  c.orbit(0.3f, 0.2f);
  Camera moved = c.camera();
  EXPECT_NEAR(glm::length(moved.position - target), 1.0f, 1e-5f);
  EXPECT_NEAR(glm::length(moved.position + 1.0f * moved.forward - target), 0.0f, 1e-5f);
  EXPECT_GT(glm::length(moved.position - cam.position), 0.1f);
  EXPECT_NEAR(glm::dot(moved.up, moved.forward), 0.0f, 1e-5f);
  // Pitch is limited short of the pole so forward never equals up.
  c.orbit(0.0f, 10.0f);
  EXPECT_LT(c.camera().forward.y, 0.9999f);
  c.zoom(5.0f);
  EXPECT_NEAR(c.distance(), std::pow(0.9f, 5.0f), 1e-5f);
  glm::vec3 before = c.target();
  c.pan(0.1f, 0.0f);
  EXPECT_NEAR(glm::length(c.target() - before), 0.1f * c.distance(), 1e-5f);
}

TEST(EditorChart, ParetoFrontKeepsOnlyUndominatedPoints) {
  std::vector<ui::ChartPoint> points(5);
  double data[5][2] = {{10, 0.5}, {20, 0.1}, {15, 0.6}, {40, 0.1}, {5, 0.9}};
  for (int i = 0; i < 5; ++i) points[i].frameMs = data[i][0], points[i].relMse = data[i][1];
  EXPECT_EQ(ui::paretoFront(points), (std::vector<std::size_t>{4, 0, 1}));
  EXPECT_TRUE(ui::paretoFront({}).empty());
}

TEST(EditorChart, PointsAreFiledUnderTheBenchMethods) {
  Settings s;
  s.clampBound = kInfinity;
  EXPECT_EQ(ui::chartMethod(s), "vpl");
  s.rejection = true;
  EXPECT_EQ(ui::chartMethod(s), "reject");
  s.clampBound = 20.0f;
  EXPECT_EQ(ui::chartMethod(s), "clamp");
  s.ssbcSteps = 2;
  EXPECT_EQ(ui::chartMethod(s), "ssbc");
  s.vslRadius = 0.05f;
  EXPECT_EQ(ui::chartMethod(s), "vsl");
  s = Settings{};
  s.clampBound = kInfinity;
  s.ssbcSteps = 2;  // SSBC without a clamp compensates nothing
  EXPECT_EQ(ui::chartMethod(s), "vpl");
}

TEST(EditorChart, LegendHasOneEntryPerMethodInTheBenchsOrderAndColours) {
  std::vector<ui::ChartPoint> points(4);
  points[0].settings.clampBound = 10.0f;
  points[1].settings.clampBound = kInfinity;
  points[2].settings.clampBound = 30.0f;
  points[3].settings.vslRadius = 0.1f;
  std::vector<ui::ChartLegendEntry> legend = ui::chartLegend(points);
  ASSERT_EQ(legend.size(), 3u);
  EXPECT_EQ(legend[0].method, "vpl");
  EXPECT_EQ(legend[1].method, "clamp");
  EXPECT_EQ(legend[2].method, "vsl");
  for (const ui::ChartLegendEntry& e : legend)
    EXPECT_EQ(e.rgb, chartColourRgb(static_cast<std::size_t>(benchMethodIndex(e.method)))) << e.method;
  EXPECT_NE(legend[0].rgb, legend[1].rgb);
  EXPECT_NE(legend[1].rgb, legend[2].rgb);
  EXPECT_TRUE(ui::chartLegend({}).empty());
}

TEST(EditorChart, LogAxisMapsDecadesLinearlyAndAlwaysHasLabelledTicks) {
  // x: left to right; y: bottom (pixel 200) to top (pixel 0).
  ui::LogAxis x = ui::fitLogAxis({1.0, 100.0}, 0.0f, 300.0f);
  EXPECT_LT(x.lo, 0.0);
  EXPECT_GT(x.hi, 2.0);
  EXPECT_GT(x.toPixel(1.0), 0.0f);  // padded: no marker on the frame
  EXPECT_LT(x.toPixel(100.0), 300.0f);
  EXPECT_NEAR(x.toPixel(10.0), 0.5f * (x.toPixel(1.0) + x.toPixel(100.0)), 1e-3f);
  EXPECT_NEAR(x.fromPixel(x.toPixel(7.0)), 7.0, 1e-4);
  EXPECT_EQ(x.ticks(), (std::vector<double>{1.0, 10.0, 100.0}));  // padded past three decades: decades only
  ui::LogAxis y = ui::fitLogAxis({1e-4, 0.01}, 200.0f, 0.0f);
  EXPECT_GT(y.toPixel(1e-4), y.toPixel(0.01));
  EXPECT_EQ(y.toPixel(0.0), 200.0f);  // an exact match pins to the bottom, never NaN
  EXPECT_EQ(y.toPixel(-1.0), 200.0f);
  // A range narrower than any tick spacing is widened until two ticks are inside.
  const std::vector<std::vector<double>> ranges = {{1.3, 1.35}, {3.0}, {}, {0.0, NAN}, {7.1e-5, 7.3e-5}};
  for (const std::vector<double>& values : ranges) {
    ui::LogAxis a = ui::fitLogAxis(values, 0.0f, 100.0f);
    std::vector<double> ticks = a.ticks();
    EXPECT_GE(ticks.size(), 2u) << values.size();
    for (double t : ticks) {
      EXPECT_GE(a.toPixel(t), 0.0f);
      EXPECT_LE(a.toPixel(t), 100.0f);
      EXPECT_FALSE(axisTickLabel(t).empty());
    }
    for (double v : values) {
      if (!(v > 0.0)) continue;
      EXPECT_TRUE(std::pow(10.0, a.lo) < v && v < std::pow(10.0, a.hi)) << v;
    }
  }
}

TEST(EditorChart, CurrentConfigurationIsFoundByItsSettings) {
  std::vector<ui::ChartPoint> points(3);
  points[0].settings.vplCount = 64;
  points[1].settings.vplCount = 128;
  points[2].settings.vplCount = 256;
  Settings current;
  current.vplCount = 128;
  EXPECT_EQ(ui::findChartPoint(points, current), 1);
  current.vplCount = 100;
  EXPECT_EQ(ui::findChartPoint(points, current), -1);
}

TEST(EditorLights, AddedLightsLightTheModelCentreWithIrradiancePi) {
  // A white plane at y = 0 under its own point light; every added light gives the plane's centre E = pi.
  Scene scene = test::makePlaneUnderPointLight(1.0f, glm::vec3(0.0f, 1.0f, 0.0f), 1.0f);
  scene.punctualLights.clear();
  ui::addLight(scene, ui::NewLight::Point);
  ui::addLight(scene, ui::NewLight::Directional);
  ui::addLight(scene, ui::NewLight::Area);
  std::vector<ui::LightHandle> lights = ui::editableLights(scene);
  ASSERT_EQ(lights.size(), 3u);
  EXPECT_EQ(lights[0].name.rfind("point", 0), 0u) << lights[0].name;
  EXPECT_EQ(lights[1].name.rfind("directional", 0), 0u) << lights[1].name;
  EXPECT_EQ(lights[2].kind, ui::LightHandle::Kind::AreaMaterial);
  const PunctualLight& point = scene.punctualLights[0];
  glm::vec3 d = point.position - glm::vec3(0.0f);  // the plane's centre (the added area light moved the bounds)
  EXPECT_NEAR(point.intensity.g / glm::dot(d, d), kPi, 1e-4);
  const PunctualLight& sun = scene.punctualLights[1];
  EXPECT_NEAR(sun.intensity.g, kPi, 1e-6);
  EXPECT_LT(sun.direction.y, 0.0f);  // from above

  // Moving a directional light does nothing; aiming it does.
  ui::moveLight(scene, lights[1], glm::vec3(1.0f));
  EXPECT_EQ(scene.punctualLights[1].position, glm::vec3(0.0f));
  ui::aimLight(scene, lights[1], glm::vec3(0.0f, -2.0f, 0.0f));
  EXPECT_EQ(scene.punctualLights[1].direction, glm::vec3(0.0f, -1.0f, 0.0f));

  // Deleting takes exactly that light.
  const std::size_t triangles = scene.triangles.size();
  ui::deleteLight(scene, lights[2]);
  EXPECT_EQ(scene.triangles.size(), triangles - 2);
  EXPECT_TRUE(scene.emissiveTriangles.empty());
  ui::deleteLight(scene, lights[0]);
  ASSERT_EQ(scene.punctualLights.size(), 1u);
  EXPECT_TRUE(scene.punctualLights[0].isDirectional());
}

TEST(EditorPresets, EveryPresetIsValidAndItsSceneExists) {
  ASSERT_GE(ui::teachingPresets().size(), 8u);
  for (const ui::TeachingPreset& p : ui::teachingPresets()) {
    EXPECT_TRUE(validateSettings(p.settings).empty()) << p.name;
    EXPECT_TRUE(std::filesystem::exists(std::string(VPLAB_TEST_ASSETS) + "/scenes/" + p.scene)) << p.name;
    EXPECT_GT(p.explanation.size(), 80u) << p.name;
    // Script lines address presets by name, which must survive the parser's rest-of-line rule.
    auto parsed = ui::parseScript("preset " + p.name + "\n", "p");
    EXPECT_EQ(parsed.at(0).args.at(0), p.name);
  }
}

// The two-rooms method preset's promise: light tracing leaves most of its VPLs in the light's room, and every
// improved generation method puts a larger share of the same budget in the camera's room (x beyond the shared
// wall's middle, 4.05 m; docs/scenes.md). Over 4 seeds with the preset's own settings.
TEST(EditorPresets, MethodPresetPutsMoreVplsInTheCamerasRoomWithEveryImprovedMethod) {
  const ui::TeachingPreset* preset = nullptr;
  for (const ui::TeachingPreset& p : ui::teachingPresets())
    if (p.name == "Where each method puts its VPLs (two rooms)") preset = &p;
  ASSERT_NE(preset, nullptr);
  auto scene = test::loadAssetScene("two-rooms");
  Settings s = preset->settings;
  s.threads = 2;
  std::vector<double> share;
  for (const GenerationVariant& v : generationVariants()) {
    applyGenerationVariant(v, s);
    double inCameraRoom = 0.0, all = 0.0;
    for (uint32_t seed = 1; seed <= 4; ++seed) {
      s.seed = seed;
      const VplSet set = generateVpls(*scene, s);
      for (const Vpl& vpl : set.vpls) inCameraRoom += vpl.position.x > 4.05f ? 1.0 : 0.0;
      all += static_cast<double>(set.vpls.size());
    }
    ASSERT_GT(all, 0.0) << v.name;
    share.push_back(inCameraRoom / all);
  }
  // Measured: 0.11 (light tracing), 0.19 (rejection), 0.24 (bidirectional), 0.38 (Metropolis).
  EXPECT_LT(share[0], 0.5) << "light tracing";
  for (std::size_t i = 1; i < share.size(); ++i)
    EXPECT_GT(share[i], 1.5 * share[0]) << generationVariants()[i].name << ": " << share[i] << " vs " << share[0];
}

TEST(EditorPresets, AnUnknownNameFailsListingEveryPresetOnALineOfItsOwn) {
  EXPECT_EQ(ui::findPreset("Corner splotches"), nullptr);
  ASSERT_NE(ui::findPreset("Corner splotches (no bound)"), nullptr);
  try {
    ui::parseScript("frames 1\npreset Corner splotches\n", "s.txt");
    FAIL() << "an unknown preset name must fail when the script is parsed";
  } catch (const ui::ScriptError& e) {
    std::istringstream lines(e.what());
    std::string first;
    std::getline(lines, first);
    EXPECT_EQ(first, "s.txt:2: no preset named 'Corner splotches'; the presets are:");
    std::vector<std::string> listed;
    for (std::string line; std::getline(lines, line);) listed.push_back(line);
    ASSERT_EQ(listed.size(), ui::teachingPresets().size());
    for (std::size_t i = 0; i < listed.size(); ++i) EXPECT_EQ(listed[i], "  " + ui::teachingPresets()[i].name);
  }
}

TEST(EditorPresets, DescriptionsSayWhatEachPresetStarts) {
  for (const ui::TeachingPreset& p : ui::teachingPresets()) {
    std::string d = ui::presetDescription(p);
    EXPECT_EQ(d.rfind("Preset: " + p.name, 0), 0u) << d;
    EXPECT_NE(d.find(p.explanation), std::string::npos) << p.name;
    EXPECT_EQ(d.find("path-traced reference") != std::string::npos, p.offline == ui::PresetOffline::Reference) << d;
    EXPECT_EQ(d.find("exact VPL render") != std::string::npos, p.offline == ui::PresetOffline::ExactVpl) << d;
    EXPECT_EQ(d.find("animates the light") != std::string::npos, p.animateLight) << d;
    if (p.offline == ui::PresetOffline::Chosen) {
      EXPECT_NE(d.find(std::string("(") + toString(p.offlineMethod) + ")"), std::string::npos) << d;
    }
    // What the presets compare against must be started by them, not left to the reader.
    const bool compares =
        p.view == ui::ViewMode::Split || p.view == ui::ViewMode::Difference || p.view == ui::ViewMode::Reference;
    EXPECT_TRUE(!compares || p.offline != ui::PresetOffline::None) << p.name;
  }
}

TEST(EditorPresets, LightAnimationClosesItsCircleOfTwoPercentOfTheDiagonal) {
  float phase = 0.0f;
  glm::vec3 position(0.0f), farthest(0.0f);
  for (int i = 0; i < ui::kLightAnimationFrames; ++i) {
    position += ui::lightAnimationStep(phase, 10.0f);
    if (glm::length(position) > glm::length(farthest)) farthest = position;
  }
  EXPECT_NEAR(glm::length(position), 0.0f, 1e-4f);
  EXPECT_NEAR(glm::length(farthest), 2.0f * 0.2f, 1e-3f);  // the circle's diameter
  EXPECT_EQ(farthest.y, 0.0f);
}

TEST(EditorTimings, AChangeCostsFromItselfUntilTheImageConvergedOverEveryFrame) {
  ui::ChangeTimer timer;
  EXPECT_LT(timer.lastMs(), 0.0) << "nothing measured yet";
  PreviewTimings partial, rest;
  partial.complete = false;
  partial.vplShadowMs = 40.0;
  partial.mediaMs = 30.0;  // a pass sliced over both frames
  rest.gatherMs = 25.0;
  rest.mediaMs = 12.0;
  rest.ssbcMs = 1.0;
  timer.changed(10.0);
  timer.vplsGenerated(5.0);
  timer.rendered(10.1, partial);
  EXPECT_TRUE(timer.pending());
  EXPECT_NEAR(timer.pendingMs(10.15), 150.0, 1e-9);
  timer.changed(10.2);  // a second change before the image caught up: still timed from the first
  timer.rendered(10.35, rest);
  EXPECT_FALSE(timer.pending());
  EXPECT_NEAR(timer.lastMs(), 350.0, 1e-9);
  EXPECT_EQ(timer.lastFrames(), 2);
  EXPECT_EQ(timer.lastPasses().vplShadowMs, 40.0);
  EXPECT_EQ(timer.lastPasses().gatherMs, 25.0);
  EXPECT_EQ(timer.lastPasses().mediaMs, 42.0);
  EXPECT_EQ(timer.lastPasses().gbufferMs, 0.0) << "a pass that did not run is cached, not timed";
  EXPECT_EQ(timer.lastVplGenerationMs(), 5.0);
  // Rendering without a change (an idle redraw) does not touch the last change's figures.
  timer.rendered(11.0, rest);
  EXPECT_NEAR(timer.lastMs(), 350.0, 1e-9);
  // The next change starts from zero: no VPL generation in it.
  timer.changed(12.0);
  timer.rendered(12.01, rest);
  EXPECT_NEAR(timer.lastMs(), 10.0, 1e-6);
  EXPECT_EQ(timer.lastFrames(), 1);
  EXPECT_EQ(timer.lastVplGenerationMs(), 0.0);
  EXPECT_EQ(timer.lastPasses().vplShadowMs, 0.0);
}

TEST(EditorTimings, OfflineRendersAreEstimatedFromTheLastRenderOfTheSameMethod) {
  ui::OfflineTimeEstimate estimate;
  Settings s;
  s.width = s.height = 100;
  s.samplesPerPixel = 10;
  EXPECT_LT(estimate.estimate(Method::Reference, s, 0), 0.0) << "unknown before the first render";
  estimate.record(Method::Reference, s, 0, 4.0);
  Settings twice = s;
  twice.samplesPerPixel = 20;
  EXPECT_NEAR(estimate.estimate(Method::Reference, twice, 0), 8.0, 1e-9);
  EXPECT_LT(estimate.estimate(Method::Vpl, s, 64), 0.0) << "methods do not share throughput";
  estimate.record(Method::Vpl, s, 64, 2.0);
  EXPECT_NEAR(estimate.estimate(Method::Vpl, s, 128), 4.0, 1e-9) << "an exact render scales with the VPLs";
  Settings vsl = s;
  vsl.vslSamples = 4;
  EXPECT_EQ(ui::OfflineTimeEstimate::work(Method::Vsl, vsl, 64), 4.0 * ui::OfflineTimeEstimate::work(Method::Vpl, s, 64));
}

TEST(EditorOffline, ExactRendersTakeTheirOwnSampleCountAndEstimateTheTimeLeft) {
  Settings s;
  s.samplesPerPixel = 64;
  s.exactSamplesPerPixel = 3;
  EXPECT_EQ(offlineRenderSettings(s, Method::Reference).samplesPerPixel, 64);
  for (Method m : {Method::Vpl, Method::VplKK, Method::Vsl})
    EXPECT_EQ(offlineRenderSettings(s, m).samplesPerPixel, 3) << toString(m);
  EXPECT_DOUBLE_EQ(ui::estimateSecondsLeft(10.0, 0.25f), 30.0);
  EXPECT_DOUBLE_EQ(ui::estimateSecondsLeft(4.0, 1.0f), 0.0);
  EXPECT_LT(ui::estimateSecondsLeft(10.0, 0.01f), 0.0) << "too little done to extrapolate";
  EXPECT_LT(ui::estimateSecondsLeft(0.1, 0.5f), 0.0) << "too early to extrapolate";
}

// --- the window, under Xvfb -----------------------------------------------------------------------------------------

struct RunResult {
  int status = -1;
  std::string output;
};

RunResult runEditor(const std::string& script, const std::string& extraArgs) {
  // In the test's own directory: CTest runs tests in parallel, and a shared script file let one test run the other's.
  const std::string scriptPath = test::tmpPath("script.txt");
  std::ofstream(scriptPath) << script;
  const std::string log = test::tmpPath("run.log"), statusFile = test::tmpPath("status.txt");
  std::remove(statusFile.c_str());
  // The editor's own exit status is written to a file: xvfb-run's replaces it with 5 when removing its temporary
  // directory fails, which happens now and then while other tests run.
  std::string cmd = "xvfb-run -a -s \"-screen 0 1280x720x24\" sh -c '" + std::string(VPLAB_BINARY) + " edit " +
                    std::string(VPLAB_TEST_ASSETS) + "/scenes/cornell-box.gltf --script " + scriptPath + " " +
                    extraArgs + " > " + log + " 2>&1; echo $? > " + statusFile + "'";
  RunResult r;
  int raw = std::system(cmd.c_str());
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  std::ifstream statusIn(statusFile);
  if (int status = 0; statusIn >> status) r.status = status;
  std::ifstream in(log);
  std::stringstream s;
  s << in.rdbuf();
  r.output = s.str();
  return r;
}

bool haveXvfb() { return std::system("command -v xvfb-run > /dev/null 2>&1") == 0; }

struct ViewRect {
  int x = 0, y = 0, w = 0, h = 0;
  float scale = 1.0f;
};

ViewRect viewRectOf(const std::string& output, const std::string& screenshot) {
  std::regex re("screenshot " + screenshot + " window \\d+x\\d+ view (\\d+) (\\d+) (\\d+) (\\d+) scale ([0-9.]+)");
  std::smatch m;
  ViewRect r;
  if (std::regex_search(output, m, re))
    r = {std::stoi(m[1]), std::stoi(m[2]), std::stoi(m[3]), std::stoi(m[4]), std::stof(m[5])};
  return r;
}

double meanChannelValue(const Image& image) {
  double sum = 0.0;
  for (const glm::vec3& p : image.pixels) sum += (p.r + p.g + p.b) / 3.0;
  return sum / static_cast<double>(image.size());
}

TEST(EditorWindow, ScriptedViewMatchesHeadlessPreviewAndKeepsVplsOnCameraMoves) {
  ASSERT_TRUE(haveXvfb()) << "xvfb-run is required (scripts/install-deps.sh installs xvfb and xauth)";
  const std::string shotA = test::tmpPath("a.png"), shotB = test::tmpPath("b.png"), viewA = test::tmpPath("a.exr"),
                    viewB = test::tmpPath("b.exr");
  std::string script =
      "set width 96\nset height 96\nset vplCount 48\nset directLightSamples 16\nframes 2\n"
      "mark\norbit 15 5\nframes 2\nexpect-no-vpl-regeneration\nexpect-no-shadow-map-render\n"
      "save-view " + viewA + "\nscreenshot " + shotA + "\n"
      "mark\nset clampBound 2\nframes 2\nexpect-no-vpl-regeneration\nexpect-no-shadow-map-render\n"
      "save-view " + viewB + "\nscreenshot " + shotB + "\ncounters\n"
      "mark\nlight 0 intensity 1.5\nframes 1\nexpect-vpl-regeneration\n";
  RunResult run = runEditor(script, "");
  ASSERT_EQ(run.status, 0) << run.output;

  // The view is not blank: the screenshot's view rectangle has light and structure.
  ViewRect rect = viewRectOf(run.output, shotA);
  ASSERT_GT(rect.w, 0) << run.output;
  ASSERT_EQ(rect.w, static_cast<int>(96 * rect.scale));
  Image screen = readPng(shotA);
  ASSERT_EQ(screen.width, 1280);
  const int scale = static_cast<int>(rect.scale);
  ASSERT_GE(scale, 1);
  Image shown(96, 96);
  for (int y = 0; y < 96; ++y)
    for (int x = 0; x < 96; ++x) shown.at(x, y) = screen.at(rect.x + x * scale + scale / 2, rect.y + y * scale + scale / 2);
  double shownMean = meanChannelValue(shown);
  EXPECT_GT(shownMean, 0.01);
  double variance = 0.0;
  for (const glm::vec3& p : shown.pixels) variance += std::pow((p.r + p.g + p.b) / 3.0 - shownMean, 2.0);
  EXPECT_GT(variance / shown.size(), 1e-4) << "the view is flat";

  // The same settings and camera through the headless preview.
  Scene scene = loadScene(std::string(VPLAB_TEST_ASSETS) + "/scenes/cornell-box.gltf");
  Settings settings = previewDefaultSettings();
  settings.width = settings.height = 96;
  settings.vplCount = 48;
  settings.directLightSamples = 16;
  OfflineScene offline(scene);
  VplSet vpls = generateVpls(offline, settings);
  ui::CameraController controller(scene.camera, glm::length(scene.bounds.center() - scene.camera.position),
                                  scene.bounds.diagonal());
  controller.orbit(glm::radians(15.0f), glm::radians(5.0f));
  HeadlessGlContext context;
  PreviewRenderer preview;
  preview.render(scene, vpls, settings, controller.camera());
  Image headlessA = preview.readLinear();
  Image editorA = readImage(viewA);
  ImageMetrics m = compareImages(editorA, headlessA);
  EXPECT_LT(m.relMse, 1e-3) << "editor view differs from the headless preview";
  EXPECT_NEAR(m.energyRatioOverall, 1.0, 0.01);

  // What is displayed is that image, tonemapped (8-bit rounding and the integer zoom aside).
  std::vector<uint8_t> expected = tonemapToRgb8(headlessA, 0.0f);
  double displayError = 0.0;
  for (std::size_t i = 0; i < shown.size(); ++i)
    for (int c = 0; c < 3; ++c)
      displayError += std::abs(static_cast<double>(quantize8(srgbFromLinear(shown.pixels[i][c]))) - expected[3 * i + c]);
  EXPECT_LT(displayError / (3.0 * shown.size()), 2.0) << "mean 8-bit difference between the window and the preview";

  // Changing b changes the image, and the result again matches a fresh headless render with the new bound.
  Image editorB = readImage(viewB);
  EXPECT_LT(meanChannelValue(editorB), 0.99 * meanChannelValue(editorA)) << "b = 2 should remove energy";
  settings.clampBound = 2.0f;
  PreviewRenderer fresh;
  fresh.render(scene, vpls, settings, controller.camera());
  EXPECT_LT(compareImages(editorB, fresh.readLinear()).relMse, 1e-3);
  EXPECT_NE(run.output.find("counters vplGenerations="), std::string::npos);
}

// A preset applied after any other preset leaves the editor as applying it first does. The script visits every
// ordered pair of presets once (an Eulerian circuit of the complete directed graph), with a frame in between: it moves
// an animated light, reseeds, starts the preview's work and the offline pass, which is what a preset can leave behind;
// the preview is fitted to the view, whose area must not depend on the preset either.
TEST(EditorWindow, EveryPresetIsTheSameAfterEveryOtherPreset) {
  ASSERT_TRUE(haveXvfb()) << "xvfb-run is required (scripts/install-deps.sh installs xvfb and xauth)";
  const std::size_t n = ui::teachingPresets().size();
  // Hierholzer's algorithm over the edges i -> j, i != j.
  std::vector<std::vector<std::size_t>> next(n);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = n; j-- > 0;)
      if (j != i) next[i].push_back(j);
  std::vector<std::size_t> stack = {0}, circuit;
  while (!stack.empty()) {
    std::size_t v = stack.back();
    if (next[v].empty()) {
      circuit.push_back(v);
      stack.pop_back();
    } else {
      stack.push_back(next[v].back());
      next[v].pop_back();
    }
  }
  ASSERT_EQ(circuit.size(), n * (n - 1) + 1);
  // A small fitted preview: the presets' own work (scene, VPLs, animation) at a tenth of the view's pixels.
  std::string script = "preview-scale 0.1\n";
  for (std::size_t v : circuit) script += "preset " + ui::teachingPresets()[v].name + "\npreset-state\nframes 1\n";
  RunResult run = runEditor(script, "");
  ASSERT_EQ(run.status, 0) << run.output;

  std::regex stateLine("preset-state (.*)");
  std::vector<std::string> states;
  std::istringstream lines(run.output);
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    if (std::regex_match(line, m, stateLine)) states.push_back(m[1]);
  }
  ASSERT_EQ(states.size(), circuit.size()) << run.output;
  std::vector<std::string> first(n);
  for (std::size_t k = 0; k < circuit.size(); ++k) {
    const std::size_t preset = circuit[k];
    if (first[preset].empty()) first[preset] = states[k];
    EXPECT_EQ(states[k], first[preset]) << ui::teachingPresets()[preset].name << " after "
                                        << ui::teachingPresets()[circuit[k - 1]].name;
  }
}

// The same for the image, on the pair that used to differ: shadow-map leaks after the flicker preset, whose light
// animation and new seeds must not carry over; and the explanation is printed with the preset.
TEST(EditorWindow, PresetImageDoesNotDependOnThePresetBefore) {
  ASSERT_TRUE(haveXvfb()) << "xvfb-run is required (scripts/install-deps.sh installs xvfb and xauth)";
  const std::string first = test::tmpPath("first.exr"), after = test::tmpPath("after.exr");
  const ui::TeachingPreset* leaks = ui::findPreset("Shadow-map leaks");
  ASSERT_NE(leaks, nullptr);
  std::string size = "set width 64\nset height 64\n";
  RunResult run = runEditor("preset Shadow-map leaks\n" + size + "save-view " + first +
                                "\npreset Flicker from reshuffled VPLs\nframes 6\npreset Shadow-map leaks\n" + size +
                                "save-view " + after + "\n",
                            "");
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find(ui::presetDescription(*leaks)), std::string::npos) << run.output;
  Image a = readImage(first), b = readImage(after);
  ASSERT_EQ(a.width, 64);
  ImageMetrics m = compareImages(b, a);
  EXPECT_EQ(m.relMse, 0.0);
  EXPECT_EQ(m.energyRatioOverall, 1.0);
}

// Without an explicit size the preview takes the view area times the resolution scale and is shown filling it;
// change-cost reports what the change of scale cost, end to end.
TEST(EditorWindow, FittedPreviewFillsTheViewAtTheResolutionScale) {
  ASSERT_TRUE(haveXvfb()) << "xvfb-run is required (scripts/install-deps.sh installs xvfb and xauth)";
  const std::string view = test::tmpPath("fitted.exr"), shot = test::tmpPath("fitted.png");
  RunResult run = runEditor("set vplCount 16\npreview-scale 0.2\nframes 3\nsave-view " + view + "\nchange-cost\n" +
                                "screenshot " + shot + "\n",
                            "");
  ASSERT_EQ(run.status, 0) << run.output;
  // The 1280 x 720 window less the two panels (340 and 370 px) and the view's margins (16 and 40 px).
  const int areaW = 1280 - 340 - 370 - 16, areaH = 720 - 40;
  Image image = readImage(view);
  EXPECT_EQ(image.width, static_cast<int>(std::lround(0.2 * areaW)));
  EXPECT_EQ(image.height, static_cast<int>(std::lround(0.2 * areaH)));
  ViewRect rect = viewRectOf(run.output, shot);
  EXPECT_TRUE(std::abs(rect.w - areaW) <= 1 || std::abs(rect.h - areaH) <= 1)
      << "the image must fill the view: " << rect.w << "x" << rect.h;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(run.output, m,
                                std::regex("change-cost size=(\\d+)x(\\d+) ms=([0-9.]+) first_image_ms=([0-9.]+) "
                                           "coarse=[01] frames=(\\d+) pending=0")))
      << run.output;
  EXPECT_EQ(std::stoi(m[1]), image.width);
  EXPECT_GT(std::stod(m[3]), 0.0);
  EXPECT_GT(std::stod(m[4]), 0.0);
  EXPECT_LE(std::stod(m[4]), std::stod(m[3]));
  EXPECT_GE(std::stoi(m[5]), 1);
}

TEST(EditorWindow, FailedExpectationExitsWithStatusOne) {
  ASSERT_TRUE(haveXvfb()) << "xvfb-run is required (scripts/install-deps.sh installs xvfb and xauth)";
  RunResult run = runEditor("set width 32\nset height 32\nset vplCount 16\nframes 1\nmark\nset vplCount 24\n"
                            "expect-no-vpl-regeneration\n",
                            "");
  EXPECT_EQ(run.status, 1) << run.output;
  EXPECT_NE(run.output.find("VPL generation(s) since the mark"), std::string::npos) << run.output;
}

TEST(EditorWindow, PanelsDrawEveryGenerationMethodAndVisibility) {
  // The panels take each control's label, tooltip and member from the settings table; every branch is drawn once.
  ASSERT_TRUE(haveXvfb()) << "xvfb-run is required (scripts/install-deps.sh installs xvfb and xauth)";
  RunResult run = runEditor("set width 32\nset height 32\nset vplCount 16\nset generation bidirectional\nframes 1\n"
                            "set generation metropolis\nframes 1\nset generation light\nset rejection true\n"
                            "set visibility ism\nset clampBound 5\nset vslRadius 0.05\nframes 1\n",
                            "");
  EXPECT_EQ(run.status, 0) << run.output;
}

// Fog added through the script's medium verbs (the media panel's functions) and drawn by the media panel, a VRL render
// beside the preview in the split view, and a refused edit that fails the script with the loader's words.
TEST(EditorWindow, MediaPanelAndTheMediaMethodsRunInTheWindow) {
  ASSERT_TRUE(haveXvfb()) << "xvfb-run is required (scripts/install-deps.sh installs xvfb and xauth)";
  const std::string shot = test::tmpPath("fog.png");
  RunResult run = runEditor("set width 32\nset height 32\nset vplCount 16\nset exactSamplesPerPixel 1\n"
                            "medium add box\nmedium 0 sigmaS 1 1.5 2\nmedium 0 g 0.4\nframes 2\nview split\n"
                            "offline vrl\nwait-offline\nframes 2\nscreenshot " + shot + "\npreset-state\n",
                            "");
  ASSERT_EQ(run.status, 0) << run.output;
  const ViewRect rect = viewRectOf(run.output, shot);
  ASSERT_GT(rect.w, 0) << run.output;
  EXPECT_NE(run.output.find("preset-state"), std::string::npos);
  RunResult refused = runEditor("medium add box\nmedium add space\n", "");
  EXPECT_EQ(refused.status, 1) << refused.output;
  EXPECT_NE(refused.output.find(":2: medium: "), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("cannot lie inside the medium that fills all space"), std::string::npos)
      << refused.output;
}

/// Pixels of the view rectangle in `shot` of the colour the view outlines a density grid's box with (orange: much red,
/// some green, little blue), which the Cornell box's red and green walls and its yellow light are not.
int smokeOutlinePixels(const std::string& shot, const ViewRect& rect) {
  const Image screen = readPng(shot);
  int count = 0;
  for (int y = rect.y; y < rect.y + rect.h; ++y)
    for (int x = rect.x; x < rect.x + rect.w; ++x) {
      const glm::vec3 c = screen.at(x, y);
      count += c.r > 0.7f && c.g > 0.2f && c.g < 0.55f * c.r && c.b < 0.15f;
    }
  return count;
}

// Smoke from a .vdb through the script's verbs (the media panel's functions), drawn by the media panel (the grid's
// figures and its density scale) and outlined in the view; a file that is no grid fails the script with its message.
TEST(EditorWindow, SmokeFromAVdbIsInTheMediaPanelAndOutlinedInTheView) {
  ASSERT_TRUE(haveXvfb()) << "xvfb-run is required (scripts/install-deps.sh installs xvfb and xauth)";
  const std::string fog = test::tmpPath("fog-box.png"), smoke = test::tmpPath("smoke-box.png");
  const std::string vdb = std::string(VPLAB_TEST_ASSETS) + "/scenes/cornell-smoke.vdb";
  RunResult run = runEditor("set width 32\nset height 32\nset vplCount 16\nmedium add box\n"
                            "medium 0 size 0.15 0.15 0.15\nframes 2\nscreenshot " + fog + "\nmedium 0 vdb " + vdb +
                                "\nmedium 0 density 2\nframes 2\nscreenshot " + smoke + "\n",
                            "");
  ASSERT_EQ(run.status, 0) << run.output;
  const ViewRect fogRect = viewRectOf(run.output, fog), smokeRect = viewRectOf(run.output, smoke);
  ASSERT_GT(smokeRect.w, 0) << run.output;
  const int before = smokeOutlinePixels(fog, fogRect), after = smokeOutlinePixels(smoke, smokeRect);
  std::printf("[ measured ] orange outline pixels in the view: %d with a fog box, %d once it holds the smoke\n", before,
              after);
  EXPECT_GT(after, before + 300) << "the grid's box must be outlined";
  RunResult refused = runEditor("medium add box\nmedium 0 vdb " + test::tmpPath("missing.vdb") + "\n", "");
  EXPECT_EQ(refused.status, 1) << refused.output;
  EXPECT_NE(refused.output.find(":2: medium: '"), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("missing.vdb': no such file"), std::string::npos) << refused.output;
}

TEST(EditorWindow, BadSceneFileIsAnErrorBeforeAnyWindow) {
  // No display needed: the scene is loaded before the window is opened.
  std::string cmd =
      std::string(VPLAB_BINARY) + " edit " + test::tmpPath("missing.gltf") + " > " + test::tmpPath("bad.log") + " 2>&1";
  int raw = std::system(cmd.c_str());
  // An input that cannot be read: exit status 3 (vplab --help lists them).
  EXPECT_EQ(WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, 3);
}

#endif  // VPLAB_HAVE_EDITOR

}  // namespace
}  // namespace vplab
