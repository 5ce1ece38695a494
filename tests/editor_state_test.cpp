// The editor's state without a window (ui/editor_state.h): an edit marks exactly the work it made stale and the
// preview re-renders that and nothing else, media edits are validated as the loader validates them, the script verbs
// reach the same functions as the panels, a .vdb opened or dropped becomes a box's smoke and a bad one changes
// nothing, the edited lights and media reopen the same, and the offline pass renders the media methods.

#ifdef VPLAB_HAVE_EDITOR

#include "ui/editor_state.h"

#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <thread>
#include <tuple>

#include "renderer/gl/context.h"
#include "renderer/image/metrics.h"
#include "renderer/invalidation.h"
#include "renderer/offline/render_methods.h"
#include "renderer/scene/density_grid.h"
#include "renderer/scene/lights_json.h"
#include "tests/gl_test_util.h"
#include "tests/test_tmp.h"
#include "ui/coarse_preview.h"
#include "ui/editor_panels.h"
#include "ui/media_panel.h"
#include "ui/script.h"
#include "ui/view_image.h"
#include "ui/vpl_overlay.h"

namespace vplab {
namespace {

const std::string kFogScene = std::string(VPLAB_TEST_ASSETS) + "/scenes/cornell-fog.gltf";
const std::string kSmokeScene = std::string(VPLAB_TEST_ASSETS) + "/scenes/cornell-smoke.gltf";
const std::string kSmokeVdb = std::string(VPLAB_TEST_ASSETS) + "/scenes/cornell-smoke.vdb";

/// Small settings: a state test is about which work runs, not about the picture.
Settings smallSettings() {
  Settings s;
  s.width = s.height = 32;
  s.vplCount = 32;
  s.directLightSamples = 4;
  s.shadowMapSize = 64;
  s.threads = 2;
  return s;
}

std::unique_ptr<ui::EditorState> fogState() {
  return std::make_unique<ui::EditorState>(kFogScene, smallSettings(), false, 0.4f);
}

// --- without GL: edits and their invalidation
// -------------------------------------------------------------------------

TEST(EditorStateMedia, InvalidMediaAreRefusedWithTheLoadersMessageAndChangeNothing) {
  auto state = fogState();  // no update runs: no GL needed
  const std::vector<Medium> before = state->media();
  ASSERT_EQ(before.size(), 1u);
  struct Case {
    std::function<void(std::vector<Medium>&)> spoil;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {[](std::vector<Medium>& m) { m[0].g = 1.0f; }, "g must lie in (-1, 1)"},
      {[](std::vector<Medium>& m) { m[0].g = NAN; }, "g must lie in (-1, 1)"},
      {[](std::vector<Medium>& m) { m[0].sigmaA.g = -0.1f; }, "sigmaA.g must lie in [0, 1e+07]"},
      {[](std::vector<Medium>& m) { m[0].sigmaS.b = INFINITY; }, "sigmaS.b must lie in [0, 1e+07]"},
      {[](std::vector<Medium>& m) { m[0].sigmaS.r = NAN; }, "sigmaS.r"},
      {[](std::vector<Medium>& m) { ui::resizeMediumBox(m[0], glm::vec3(0.1f, 0.0f, 0.1f)); }, "no volume"},
      {[](std::vector<Medium>& m) { m.push_back(m[0]); }, "medium boxes overlap"},
      {[&](std::vector<Medium>& m) { m.push_back(ui::newFogEverywhere(state->scene())); },
       "cannot lie inside the medium that fills all space"},
  };
  for (const Case& c : cases) {
    std::vector<Medium> next = before;
    c.spoil(next);
    EXPECT_FALSE(state->editMedia(next)) << c.expected;
    EXPECT_NE(state->mediaError().find(c.expected), std::string::npos) << state->mediaError();
    ASSERT_EQ(state->media().size(), before.size());
    EXPECT_EQ(state->media()[0].sigmaS, before[0].sigmaS);
    EXPECT_EQ(state->media()[0].worldFromBox, before[0].worldFromBox);
  }
  // A valid edit clears the message.
  std::vector<Medium> next = before;
  next[0].g = 0.5f;
  EXPECT_TRUE(state->editMedia(next));
  EXPECT_TRUE(state->mediaError().empty());
  EXPECT_EQ(state->media()[0].g, 0.5f);
}

TEST(EditorStateMedia, CoefficientsAndBoxesStaleTheVplsButNeitherTheGBufferNorTheShadowMaps) {
  auto state = fogState();
  const std::vector<Medium> fog = state->media();
  auto after = [&](const std::function<void(std::vector<Medium>&)>& edit) {
    std::vector<Medium> next = fog;
    edit(next);
    return staleAfterMediumEdit(fog, next);
  };
  for (const auto& edit : std::vector<std::function<void(std::vector<Medium>&)>>{
           [](std::vector<Medium>& m) { m[0].sigmaS *= 1.02f; }, [](std::vector<Medium>& m) { m[0].sigmaA.r += 0.01f; },
           [](std::vector<Medium>& m) { m[0].g = -0.2f; },
           [](std::vector<Medium>& m) { ui::moveMediumBox(m[0], glm::vec3(0.0f, -0.01f, 0.0f)); },
           [](std::vector<Medium>& m) { ui::resizeMediumBox(m[0], 0.5f * m[0].halfSizes()); },
           [](std::vector<Medium>& m) { m.clear(); }}) {
    const Staleness s = after(edit);
    EXPECT_TRUE(s.vpls && s.vplShadowMaps && s.gather && s.direct && s.offline) << toString(s);
    EXPECT_FALSE(s.gbuffer || s.lightShadowMaps) << toString(s);
  }
  // What light does not meet changes nothing: a new name, a vacuum box added.
  EXPECT_EQ(after([](std::vector<Medium>& m) { m[0].name = "renamed"; }), Staleness{});
  EXPECT_EQ(after([&](std::vector<Medium>& m) {
              Medium vacuum = ui::newFogBox(state->scene());
              vacuum.sigmaA = vacuum.sigmaS = glm::vec3(0.0f);
              ui::moveMediumBox(vacuum, glm::vec3(10.0f));
              m.push_back(vacuum);
            }),
            Staleness{});
  // The bound b does not touch the VPLs, in media as elsewhere; it re-gathers.
  Settings b = state->settings();
  b.clampBound = 5.0f;
  const Staleness bound = staleAfterSettingsChange(state->settings(), b, Method::VplAbc);
  EXPECT_FALSE(bound.vpls || bound.vplShadowMaps) << toString(bound);
  EXPECT_TRUE(bound.gather && bound.offline) << toString(bound);
}

TEST(EditorStateMedia, NewBoxesFitTheGeometryAndMovingOrResizingKeepsTheRest) {
  auto state = fogState();
  const Scene& scene = state->scene();
  Medium box = ui::newFogBox(scene);
  EXPECT_TRUE(mediumProblem(box).empty()) << mediumProblem(box);
  for (const glm::vec3& corner : box.corners())
    for (int a = 0; a < 3; ++a) {
      EXPECT_GT(corner[a], scene.geometryBounds.lower[a]);
      EXPECT_LT(corner[a], scene.geometryBounds.upper[a]);
    }
  const glm::vec3 centre = box.centre();
  ui::resizeMediumBox(box, glm::vec3(0.1f, 0.2f, 0.3f));
  EXPECT_NEAR(glm::length(box.centre() - centre), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::length(box.halfSizes() - glm::vec3(0.1f, 0.2f, 0.3f)), 0.0f, 1e-6f);
  ui::moveMediumBox(box, glm::vec3(0.5f, 0.0f, -0.25f));
  EXPECT_NEAR(glm::length(box.centre() - centre - glm::vec3(0.5f, 0.0f, -0.25f)), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::length(box.halfSizes() - glm::vec3(0.1f, 0.2f, 0.3f)), 0.0f, 1e-6f);
  EXPECT_EQ(mediumAt({box}, box.centre()), 0);
  // The panel's figures: 1 / sigma_t, and sigma_t times the lengths.
  box.sigmaA = glm::vec3(0.5f);
  box.sigmaS = glm::vec3(1.5f, 0.0f, 0.0f);
  const std::string text = ui::describeMedium(box, 2.0f);
  EXPECT_NE(text.find("mean free path 0.5 2 2 m"), std::string::npos) << text;
  EXPECT_NE(text.find("across the scene 4 1 1"), std::string::npos) << text;
  EXPECT_NE(text.find("longest edge 1.2 0.3 0.3"), std::string::npos) << text;
}

TEST(EditorStateMedia, DensityGridsAreDescribedByTheirDensestVoxel) {
  ui::EditorState state(kSmokeScene, smallSettings(), false, 0.4f);
  Medium smoke = state.media().at(0);
  ASSERT_TRUE(smoke.heterogeneous());
  smoke.densityScale = 2.5f;
  // The same figures as a homogeneous box at the grid's peak sigma_t, each marked as a bound.
  Medium peak = smoke;
  peak.density = nullptr;
  const float densest = smoke.densityScale * smoke.density->maxValue;
  peak.sigmaA *= densest;
  peak.sigmaS *= densest;
  std::string text = ui::describeMedium(smoke, 2.0f);
  EXPECT_EQ(text.find("mean free path down to "), 0u) << text;
  EXPECT_NE(text.find("across the scene up to "), std::string::npos) << text;
  EXPECT_NE(text.find("longest edge up to "), std::string::npos) << text;
  for (const std::string bound : {"down to ", "up to "})
    for (std::size_t at; (at = text.find(bound)) != std::string::npos;) text.erase(at, bound.size());
  EXPECT_EQ(text, ui::describeMedium(peak, 2.0f));
}

TEST(EditorStateMedia, AVdbGoesToTheSelectedBoxElseTheFirstElseANewOne) {
  auto state = fogState();
  const Scene& scene = state->scene();
  Medium second = ui::newFogBox(scene);
  ui::resizeMediumBox(second, glm::vec3(0.05f));
  ui::moveMediumBox(second, glm::vec3(10.0f));
  const std::vector<Medium> boxes = {state->media().at(0), second};
  EXPECT_EQ(ui::densityTarget(boxes, 1), 1);
  EXPECT_EQ(ui::densityTarget(boxes, -1), 0);
  EXPECT_EQ(ui::densityTarget(boxes, 7), 0);
  EXPECT_EQ(ui::densityTarget({ui::newFogEverywhere(scene), second}, 0), 1) << "all space cannot hold a grid";
  EXPECT_EQ(ui::densityTarget({ui::newFogEverywhere(scene)}, 0), -1);
  EXPECT_EQ(ui::densityTarget({}, -1), -1);

  // Into the selected box: the grid fills it, named by the panel's grid field.
  ui::MediaPanelInput input;
  input.selected = 1;
  std::vector<Medium> media = boxes;
  ASSERT_TRUE(ui::openVdb(scene, media, input, kSmokeVdb)) << input.vdbError;
  EXPECT_TRUE(input.vdbError.empty());
  EXPECT_FALSE(media[0].heterogeneous());
  ASSERT_TRUE(media[1].heterogeneous());
  EXPECT_EQ(media[1].densityGridName, "density");
  EXPECT_EQ(std::filesystem::path(media[1].densityUri).filename(), "cornell-smoke.vdb");
  EXPECT_EQ(media[1].centre(), second.centre());
  EXPECT_TRUE(mediaProblem(media).empty()) << mediaProblem(media);

  // A file that cannot give a grid: its message, and nothing changed.
  for (const auto& [path, grid, expected] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {test::tmpPath("missing.vdb"), "density", "no such file"},
           {kSmokeScene, "density", "not a readable OpenVDB file"},
           {kSmokeVdb, "smoke", "no grid named 'smoke' (grids: density"}}) {
    input.gridName = grid;
    const std::vector<Medium> before = media;
    EXPECT_FALSE(ui::openVdb(scene, media, input, path)) << path;
    EXPECT_NE(input.vdbError.find(expected), std::string::npos) << input.vdbError;
    ASSERT_EQ(media.size(), before.size());
    for (std::size_t i = 0; i < media.size(); ++i) {
      EXPECT_EQ(media[i].density, before[i].density);
      EXPECT_EQ(media[i].worldFromBox, before[i].worldFromBox);
    }
  }

  // Without a box, a new one named after the file, selected.
  input = ui::MediaPanelInput{};
  media.clear();
  ASSERT_TRUE(ui::openVdb(scene, media, input, kSmokeVdb)) << input.vdbError;
  ASSERT_EQ(media.size(), 1u);
  EXPECT_TRUE(media[0].heterogeneous());
  EXPECT_EQ(media[0].name, "cornell-smoke");
  EXPECT_EQ(input.selected, 0);
}

// The view outlines each medium box: the smoke's box is its grid's bounds, so it is drawn as any box is.
TEST(EditorStateMedia, TheViewOutlinesEveryBoxClippedAtTheNearPlane) {
  ui::EditorState state(kSmokeScene, smallSettings(), false, 0.4f);
  const Camera camera = state.scene().camera;
  const Medium& smoke = state.media().at(0);
  const std::vector<std::array<glm::vec2, 2>> edges = ui::mediumBoxOutline(smoke, camera, 1.0f);
  ASSERT_EQ(edges.size(), 12u) << "the box lies in front of the scene camera";
  // Each edge joins the projections of two corners that differ along one of the box's axes.
  const std::vector<glm::vec3> corners = smoke.corners();
  for (const auto& edge : edges) {
    int ends = 0;
    for (const glm::vec3& c : corners) {
      const glm::vec2 p = ui::projectToImage(camera, 1.0f, c).value();
      ends += glm::length(p - edge[0]) < 1e-5f || glm::length(p - edge[1]) < 1e-5f;
    }
    EXPECT_EQ(ends, 2);
  }
  // A camera inside the box sees the part in front of it, finite; nothing of a medium filling all space.
  Camera inside = camera;
  inside.position = smoke.centre();
  const std::vector<std::array<glm::vec2, 2>> around = ui::mediumBoxOutline(smoke, inside, 1.0f);
  EXPECT_GT(around.size(), 0u);
  EXPECT_LT(around.size(), 12u);
  for (const auto& edge : around)
    for (const glm::vec2& p : edge) EXPECT_TRUE(std::isfinite(p.x) && std::isfinite(p.y));
  EXPECT_TRUE(ui::mediumBoxOutline(ui::newFogEverywhere(state.scene()), camera, 1.0f).empty());
}

// The window's drop callback: a .vdb becomes smoke through editMedia (a bad one leaves the media and says why); any
// other file opens as a scene, as a dropped .gltf always did.
TEST(EditorStateMedia, ADroppedVdbBecomesSmokeAndADroppedSceneOpens) {
  ui::EditorState state(std::string(VPLAB_TEST_ASSETS) + "/scenes/cornell-box.gltf", smallSettings(), false, 0.4f);
  ui::PanelState panels;
  ASSERT_TRUE(state.media().empty());
  ui::openDroppedFile(state, panels, test::tmpPath("missing.VDB"));
  EXPECT_NE(panels.media.vdbError.find("no such file"), std::string::npos) << panels.media.vdbError;
  EXPECT_TRUE(state.media().empty());
  EXPECT_TRUE(panels.revealMedia) << "the media section opens to show why";
  ui::openDroppedFile(state, panels, kSmokeVdb);
  EXPECT_TRUE(panels.media.vdbError.empty()) << panels.media.vdbError;
  ASSERT_EQ(state.media().size(), 1u);
  EXPECT_TRUE(state.media()[0].heterogeneous());
  EXPECT_TRUE(state.mediaError().empty()) << state.mediaError();
  ui::openDroppedFile(state, panels, kFogScene);
  EXPECT_EQ(std::filesystem::path(state.scene().sourcePath).filename(), "cornell-fog.gltf");
  EXPECT_FALSE(state.media().at(0).heterogeneous());
}

// --- with GL: the preview re-renders what the edit made stale --------------------------------------------------------

class EditorStateGl : public ::testing::Test {
 protected:
  HeadlessGlContext context_;
};

TEST_F(EditorStateGl, EachEditRendersWhatItMadeStaleAndNothingElse) {
  auto state = fogState();
  state->finishWork();
  ASSERT_TRUE(state->previewError().empty()) << state->previewError();
  ASSERT_FALSE(state->previewImage().empty());
  EXPECT_EQ(state->counters().vplGenerations, 1);

  // The bound b: a new gather, the same VPLs and shadow maps.
  Image before = state->previewImage();
  state->mark();
  Settings b = state->settings();
  b.clampBound = 2.0f;
  state->changeSettings(b);
  ui::WorkCounters n = state->sinceMark();
  EXPECT_EQ(n.vplGenerations, 0);
  EXPECT_EQ(n.vplShadowMaps, 0);
  EXPECT_GE(n.gathers, 1);
  EXPECT_LT(compareImages(state->previewImage(), before).energyRatioOverall, 0.999) << "b = 2 removes energy";

  // A fog coefficient: new VPLs (same seed, other flux and places), their shadow maps, a gather.
  const std::vector<Vpl> oldVpls = state->vpls().vpls;
  before = state->previewImage();
  state->mark();
  std::vector<Medium> media = state->media();
  media[0].sigmaS *= 3.0f;
  ASSERT_TRUE(state->editMedia(media));
  n = state->sinceMark();
  EXPECT_EQ(n.vplGenerations, 1);
  EXPECT_GT(n.vplShadowMaps, 0);
  EXPECT_GE(n.gathers, 1);
  bool vplsDiffer = oldVpls.size() != state->vpls().vpls.size();
  for (std::size_t i = 0; !vplsDiffer && i < oldVpls.size(); ++i)
    vplsDiffer = oldVpls[i].flux != state->vpls().vpls[i].flux || oldVpls[i].position != state->vpls().vpls[i].position;
  EXPECT_TRUE(vplsDiffer);
  EXPECT_GT(compareImages(state->previewImage(), before).relMse, 0.0);

  // A camera move: a new G-buffer and gather, never new VPLs or shadow maps.
  state->mark();
  state->camera().orbit(0.1f, 0.0f);
  state->cameraMoved();
  n = state->sinceMark();
  EXPECT_EQ(n.vplGenerations, 0);
  EXPECT_EQ(n.vplShadowMaps, 0);
  EXPECT_GE(n.gathers, 1);

  // A renamed medium: nothing at all.
  state->mark();
  media = state->media();
  media[0].name = "renamed";
  ASSERT_TRUE(state->editMedia(media));
  n = state->sinceMark();
  EXPECT_EQ(n.vplGenerations, 0);
  EXPECT_EQ(n.vplShadowMaps, 0);
  EXPECT_EQ(n.gathers, 0);
}

// A slow change shows its new state at a quarter of the pixels first (CoarsePreview): neither the old image nor a mix,
// and then the full-size image, the one an update without a coarse image gives.
TEST_F(EditorStateGl, ASlowChangeShowsACoarseImageOfTheNewStateFirst) {
  auto state = fogState();
  state->coarseFirstAfterMs = 0.0;  // every change after the first update counts as slow
  state->finishWork();
  ASSERT_TRUE(state->previewError().empty()) << state->previewError();
  const Image before = state->previewImage();
  state->camera().orbit(0.3f, 0.0f);
  state->cameraMoved();
  state->updateWork(0.0);  // the full-size update stops after its first slice
  // The full-size update is left at least 1 ms after the coarse image: an NVIDIA H200 through EGL finishes the whole
  // camera move within it, and shows the final image at once; llvmpipe takes many calls.
  if (!state->previewUpdating()) GTEST_SKIP() << "the full-size update finished within one call: no coarse image shown";
  const Settings& settings = state->settings();
  PreviewRenderer coarse;
  coarse.render(state->scene(), state->vpls(), ui::CoarsePreview::coarseSettings(settings), state->camera().camera());
  const Image coarseImage = coarse.readLinear();
  ASSERT_EQ(coarseImage.width, settings.width / 2);
  EXPECT_EQ(test::differingPixels(state->previewImage(), resizedBilinear(coarseImage, settings.width, settings.height)),
            0u);
  EXPECT_GT(compareImages(state->previewImage(), before).relMse, 1e-3) << "the old camera's image is shown";

  state->finishWork();
  PreviewRenderer full;
  full.render(state->scene(), state->vpls(), settings, state->camera().camera());
  EXPECT_EQ(test::differingPixels(state->previewImage(), full.readLinear()), 0u);
  EXPECT_TRUE(state->changeTimer().lastHadCoarseImage());
  EXPECT_GT(state->changeTimer().lastFirstImageMs(), 0.0);
  EXPECT_LE(state->changeTimer().lastFirstImageMs(), state->changeTimer().lastMs());

  // A change while the last update took no longer than coarseFirstAfterMs: the final image is the first.
  state->coarseFirstAfterMs = std::numeric_limits<double>::infinity();
  state->camera().orbit(-0.3f, 0.0f);
  state->cameraMoved();
  state->finishWork();
  EXPECT_FALSE(state->changeTimer().lastHadCoarseImage());
  EXPECT_EQ(state->changeTimer().lastFirstImageMs(), state->changeTimer().lastMs());
}

// A slider dragged while an update runs: the update finishes with the media it started with (an image every time one
// finishes, instead of a restart every frame), then the next one takes the latest edit.
TEST_F(EditorStateGl, AMediumDraggedDuringAnUpdateWaitsForIt) {
  auto state = fogState();
  state->finishWork();
  const glm::vec3 sigmaS = state->media()[0].sigmaS;
  std::vector<Medium> media = state->media();
  media[0].sigmaS *= 1.5f;
  ASSERT_TRUE(state->editMedia(media));
  state->updateWork(0.0);  // starts the update: at least one pass, then out of budget
  ASSERT_TRUE(state->previewUpdating()) << "a zero budget must leave passes for later frames";
  const int finished = state->updatesFinished();
  for (int frame = 0; state->previewUpdating(); ++frame) {
    ASSERT_LT(frame, 1000) << "the update must finish while the slider moves";
    media[0].sigmaS *= 1.01f;  // the drag goes on
    ASSERT_TRUE(state->editMedia(media));
    state->updateWork(0.0);
  }
  EXPECT_EQ(state->updatesFinished(), finished + 1);
  EXPECT_EQ(state->scene().media[0].sigmaS, sigmaS * 1.5f) << "the finished image is of the media it started with";
  EXPECT_EQ(state->media()[0].sigmaS, media[0].sigmaS) << "the panel shows the latest edit";
  state->finishWork();
  EXPECT_EQ(state->scene().media[0].sigmaS, media[0].sigmaS) << "which the next update takes";
}

TEST_F(EditorStateGl, ScriptVerbsCallTheStateFunctionsWithoutAWindow) {
  auto state = fogState();
  const std::vector<ui::ScriptCommand> script = ui::parseScript(
      "mark\nset clampBound 5\nexpect-no-vpl-regeneration\nexpect-no-shadow-map-render\n"
      "medium 0 sigmaS 0.4 0.4 0.4\nexpect-vpl-regeneration\nmedium 0 remove\nmedium add box\n"
      "medium 0 sigmaS 0.5 0.5 0.5\nmedium 0 g -0.3\nmedium 0 size 0.2 0.2 0.2\nmedium 0 move 0 -0.05 0\n"
      "view split\nframes 2\n",
      "s.txt");
  std::vector<std::string> windowVerbs;
  for (const ui::ScriptCommand& c : script)
    if (!ui::runStateCommand(*state, c, "s.txt")) windowVerbs.push_back(c.verb);
  EXPECT_EQ(windowVerbs, std::vector<std::string>{"frames"});
  const Medium& fog = state->media().at(0);
  EXPECT_EQ(fog.sigmaS, glm::vec3(0.5f));
  EXPECT_EQ(fog.g, -0.3f);
  EXPECT_NEAR(fog.halfSizes().x, 0.2f, 1e-6f);
  EXPECT_EQ(state->view().view, ui::ViewMode::Split);
  EXPECT_EQ(state->settings().clampBound, 5.0f);
  // An edit the loader would refuse fails the script at its line with the loader's words, and changes nothing.
  for (const std::string bad :
       {"medium 0 g 1", "medium 0 sigmaA -1 0 0", "medium add space", "medium add box", "medium 3 g 0"}) {
    try {
      ui::runStateCommand(*state, ui::parseScript("frames 1\n" + bad + "\n", "s.txt").at(1), "s.txt");
      ADD_FAILURE() << "no error for " << bad;
    } catch (const ui::ScriptError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("s.txt:2: medium: ", 0), 0u) << e.what();
    }
  }
  EXPECT_EQ(state->media().size(), 1u);
  EXPECT_EQ(state->media()[0].g, -0.3f);
  EXPECT_THROW(ui::parseScript("medium 0 spin 3\n", "s.txt"), ui::ScriptError);
  EXPECT_THROW(ui::parseScript("offline fast\n", "s.txt"), ui::ScriptError);
}

/// Runs one script line on the state as line 2 of s.txt; the ScriptError's message, or empty.
std::string scriptError(ui::EditorState& state, const std::string& line) {
  try {
    ui::runStateCommand(state, ui::parseScript("frames 1\n" + line + "\n", "s.txt").at(1), "s.txt");
  } catch (const ui::ScriptError& e) {
    return e.what();
  }
  return {};
}

TEST_F(EditorStateGl, DensityVerbsScaleAndAttachGridsThroughTheMediumEditPath) {
  ui::EditorState state(kSmokeScene, smallSettings(), false, 0.4f);
  state.finishWork();
  ASSERT_TRUE(state.media().at(0).heterogeneous());
  // The scale: a medium edit, so new VPLs (the light paths scatter elsewhere).
  state.mark();
  EXPECT_EQ(scriptError(state, "medium 0 density 2.5"), "");
  EXPECT_EQ(state.media()[0].densityScale, 2.5f);
  EXPECT_EQ(state.sinceMark().vplGenerations, 1);
  EXPECT_EQ(state.scene().media[0].densityScale, 2.5f) << "the scene took it with the update";
  // Refused: a negative scale (the loader's words), a scale without a grid, a medium that does not exist.
  const std::string negative = scriptError(state, "medium 0 density -1");
  EXPECT_EQ(negative.rfind("s.txt:2: medium: ", 0), 0u) << negative;
  EXPECT_NE(negative.find("density scale must lie in [0, "), std::string::npos) << negative;
  EXPECT_EQ(state.media()[0].densityScale, 2.5f);
  EXPECT_NE(scriptError(state, "medium 1 density 2").find("no medium 1"), std::string::npos);

  // A grid onto the fog box: it becomes the grid's box, with new VPLs.
  ui::EditorState fog(kFogScene, smallSettings(), false, 0.4f);
  fog.finishWork();
  EXPECT_NE(scriptError(fog, "medium 0 density 2").find("has no density grid; 'medium 0 vdb <path>'"),
            std::string::npos);
  const Medium box = fog.media().at(0);
  for (const std::string& bad :
       {"medium 0 vdb " + test::tmpPath("missing.vdb"), "medium 0 vdb " + kSmokeVdb + " smoke"}) {
    const std::string error = scriptError(fog, bad);
    EXPECT_EQ(error.rfind("s.txt:2: medium: '", 0), 0u) << error;
    EXPECT_FALSE(fog.media().at(0).heterogeneous()) << bad;
    EXPECT_EQ(fog.media()[0].worldFromBox, box.worldFromBox) << bad;
  }
  fog.mark();
  EXPECT_EQ(scriptError(fog, "medium 0 vdb " + kSmokeVdb), "");
  const Medium& smoke = fog.media().at(0);
  ASSERT_TRUE(smoke.heterogeneous());
  EXPECT_EQ(smoke.densityGridName, "density");
  EXPECT_EQ(smoke.sigmaS, box.sigmaS) << "the coefficients stay, now per unit density";
  EXPECT_NE(smoke.worldFromBox, box.worldFromBox) << "the box is the grid's, fitted into the old one";
  EXPECT_EQ(fog.sinceMark().vplGenerations, 1);
  EXPECT_EQ(scriptError(fog, "medium 0 vdb " + kSmokeVdb + " density"), "") << "the grid named";

  // Parsing: the path is no number, the scale is.
  EXPECT_THROW(ui::parseScript("medium 0 vdb\n", "s.txt"), ui::ScriptError);
  EXPECT_THROW(ui::parseScript("medium 0 vdb a.vdb density extra\n", "s.txt"), ui::ScriptError);
  EXPECT_THROW(ui::parseScript("medium 0 density thick\n", "s.txt"), ui::ScriptError);
  EXPECT_NO_THROW(ui::parseScript("medium 0 vdb smoke.vdb plume\nmedium 0 density 0.5\n", "s.txt"));
}

TEST_F(EditorStateGl, EditedLightsAndMediaReopenTheSame) {
  // A copy of the scene in the test's directory: the sidecar goes next to it.
  const std::string copy = test::tmpPath("cornell-fog.gltf");
  std::filesystem::copy_file(kFogScene, copy, std::filesystem::copy_options::overwrite_existing);
  std::filesystem::remove(lightsSidecarPath(copy));
  std::string saved;
  {
    ui::EditorState state(copy, smallSettings(), false, 0.4f);
    const std::vector<ui::ScriptCommand> script = ui::parseScript(
        "medium 0 sigmaA 0.2 0.1 0.05\nmedium 0 g 0.6\nmedium 0 size 0.2 0.2 0.2\nlight 0 intensity 2\n"
        "save-sidecar\n",
        "s.txt");
    for (const ui::ScriptCommand& c : script) ui::runStateCommand(state, c, "s.txt");
    state.finishWork();  // the scene takes the edited media with the next update
    saved = lightsToJson(state.scene());
  }
  ui::EditorState reopened(copy, smallSettings(), false, 0.4f);
  EXPECT_EQ(lightsToJson(reopened.scene()), saved);
  ASSERT_EQ(reopened.scene().media.size(), 1u);
  EXPECT_EQ(reopened.scene().media[0].g, 0.6f);
  EXPECT_EQ(reopened.scene().media[0].sigmaA, glm::vec3(0.2f, 0.1f, 0.05f));
  std::filesystem::remove(lightsSidecarPath(copy));
}

/// Polls the state until its offline job ended and its last image is taken.
void waitForOffline(ui::EditorState& state) {
  while (state.job().running()) {
    state.pollOffline();
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  state.pollOffline();
}

TEST_F(EditorStateGl, OfflinePassRendersTheMediaMethodsOfTheTable) {
  auto state = fogState();
  Settings s = state->settings();
  s.width = s.height = 12;
  s.vplCount = 16;
  s.exactSamplesPerPixel = 1;
  s.beamPasses = 3;
  state->changeSettings(s);
  state->finishWork();
  for (Method method : {Method::VplAbc, Method::Vrl, Method::Vbl}) {
    state->setOfflineMethod(method);
    state->startOffline(ui::OfflineRequest::Chosen);
    waitForOffline(*state);
    ASSERT_TRUE(state->job().error().empty()) << state->job().error();
    EXPECT_EQ(state->offlineImageMethod(), method);
    // The same image as the render-method table gives for the same scene, camera, settings and VPLs.
    Scene scene = state->scene();
    scene.camera = state->camera().camera();
    OfflineScene offline(scene);
    const VplRenderResult direct = renderMethod(method).render(
        offline, state->vpls(), offlineRenderSettings(state->settings(), method), nullptr, {});
    const ImageMetrics m = compareImages(state->offlineImage(), direct.image);
    EXPECT_LT(m.relMse, 1e-6) << toString(method);
    EXPECT_GT(m.energyRatioOverall, 0.0) << toString(method);
    // The next render of the same method with the same settings is estimated at what this one took.
    EXPECT_NEAR(state->offlineEstimate(method), state->offlineSeconds(), 1e-6 + 1e-6 * state->offlineSeconds())
        << toString(method);
  }
  // The composed split view puts that image right of the divider, at the preview's size.
  state->setView(ui::ViewMode::Split);
  const ui::ViewImage view = ui::composeView(*state);
  EXPECT_TRUE(view.emptyState.empty()) << view.emptyState;
  EXPECT_EQ(view.width, 12);
}

}  // namespace
}  // namespace vplab

#endif  // VPLAB_HAVE_EDITOR
