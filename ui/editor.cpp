#include "ui/editor.h"

#include "evaluation/sweep.h"
#include "renderer/gl/context.h"
#include "renderer/gl/preview_renderer.h"
#include "renderer/image/heatmap.h"
#include "renderer/image/image_io.h"
#include "renderer/image/metrics.h"
#include "renderer/image/tonemap.h"
#include "renderer/invalidation.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/core/atomic_file.h"
#include "renderer/offline/light_sampler.h"
#include "renderer/scene/brdf_params.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/lights_json.h"
#include "renderer/scene/staging.h"
#include "renderer/settings_json.h"
#include "renderer/vpl/generation_methods.h"
#include "renderer/vpl/vpl_contribution.h"
#include "renderer/vpl/vpl_generation.h"
#include "renderer/vpl/vpl_importance.h"
#include "ui/camera_controller.h"
#include "ui/change_timer.h"
#include "ui/chart.h"
#include "ui/offline_job.h"
#include "ui/panels.h"
#include "ui/presets.h"
#include "ui/script.h"
#include "ui/vpl_overlay.h"

// glad first: it must define the GL prototypes before GLFW looks for any.
#include <glad/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <stdexcept>

namespace vplab::ui {

namespace {

constexpr float kLeftPanelWidth = 340.0f;
// Window clear colour, which is also the panels' background (see Editor's ImGui style set-up).
constexpr float kBackground[3] = {0.07f, 0.07f, 0.075f};
constexpr float kRightPanelWidth = 370.0f;
/// Height of the active preset's explanation above the view (a longer text scrolls inside it). Fixed, so that the
/// view area, and a fitted preview's size, is the same for every preset.
constexpr float kPresetBoxHeight = 150.0f;

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// "850 ms", "12 s", "3 min 20 s".
std::string formatSeconds(double seconds) {
  char text[32];
  if (seconds < 1.0)
    std::snprintf(text, sizeof text, "%.0f ms", seconds * 1e3);
  else if (seconds < 120.0)
    std::snprintf(text, sizeof text, "%.0f s", std::ceil(seconds));
  else
    std::snprintf(text, sizeof text, "%.0f min %.0f s", std::floor(seconds / 60.0), std::fmod(std::ceil(seconds), 60.0));
  return text;
}

float luminance(const glm::vec3& c) {
  return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
}

std::string recentFilesPath() {
  const char* home = std::getenv("HOME");
  return home ? std::string(home) + "/.vplab_recent" : std::string();
}

/// A GL texture showing 8-bit sRGB pixels, copied into the window by a framebuffer blit: nearest at integer zoom,
/// linear when the image is scaled to fit the view.
class DisplayTexture {
 public:
  ~DisplayTexture() {
    if (framebuffer_) glDeleteFramebuffers(1, &framebuffer_);
    if (id_) glDeleteTextures(1, &id_);
  }
  void upload(int width, int height, const std::vector<uint8_t>& rgb) {
    if (!id_) {
      glGenTextures(1, &id_);
      glBindTexture(GL_TEXTURE_2D, id_);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    glBindTexture(GL_TEXTURE_2D, id_);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, width, height, 0, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
    width_ = width;
    height_ = height;
  }
  /// Copies the image into the bound draw framebuffer at (x, y, w, h) in window pixels from the top left of a window
  /// `windowHeight` pixels high. A blit, not a textured quad through ImGui: under llvmpipe it skips blending and
  /// texture filtering for the largest thing on screen.
  void blitTo(float x, float y, float w, float h, int windowHeight, bool smooth) {
    if (!id_) return;
    if (!framebuffer_) glGenFramebuffers(1, &framebuffer_);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_);
    glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, id_, 0);
    // The image's first row is its top and sits at texture row 0; window rows count from the bottom.
    const int x0 = static_cast<int>(x), x1 = static_cast<int>(x + w);
    const int top = windowHeight - static_cast<int>(y), bottom = windowHeight - static_cast<int>(y + h);
    glBlitFramebuffer(0, 0, width_, height_, x0, top, x1, bottom, GL_COLOR_BUFFER_BIT, smooth ? GL_LINEAR : GL_NEAREST);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  }
  int width() const { return width_; }
  int height() const { return height_; }
  bool valid() const { return id_ != 0; }

 private:
  GLuint id_ = 0, framebuffer_ = 0;
  int width_ = 0, height_ = 0;
};

struct WorkCounters {
  int vplGenerations = 0;
  int vplShadowMaps = 0;
  int gathers = 0;
};

class Editor {
 public:
  explicit Editor(const EditorOptions& options);
  ~Editor();
  int run();

 private:
  // --- scene and lights ---
  bool openScene(const std::string& path, bool keepSettingsSize = true);
  void rebuildAcceleration();
  void editLight(std::size_t light, const glm::vec3& offset, float scale);
  /// Rebuilds what a light edit made stale (the BVH now; the preview's maps when its next update starts).
  void applyLightEdit(LightEdit edit);

  // --- work ---
  void markStale(const Staleness& s);
  void changeSettings(const Settings& next);
  void updateWork();
  /// updateWork() until the preview is complete (script verbs that read the image or the counters).
  void finishWork();
  void regenerateVpls();
  void measureClampEnergy();
  void composeDisplay();
  /// The empty-state message of a view that needs an offline result of the preview's size.
  std::string offlineMismatch(const std::string& what) const;
  /// The empty state in the middle of the view area: the message, and the render buttons or the running job.
  void drawEmptyState(float x, float y, float width, float height);
  /// The view, its size, what the last change cost, this frame's time and the VPL count, at (x, y).
  void drawStatusBar(float x, float y);
  /// previewScale_ times the space the view has for the image (window pixels), with or without the preset box.
  glm::ivec2 fittedPreviewSize(bool presetBox) const;
  void addChartPoint();
  void startOffline(bool reference);
  void pollOffline();
  /// Applies a teaching preset from scratch: its scene reloaded (lights as in the file, the scene camera), its
  /// complete settings, its view and view options, and what it starts.
  bool applyPreset(const TeachingPreset& preset);
  /// The preset's settings as applied here: this machine's thread count, the fitted preview's size.
  Settings presetSettingsHere(const TeachingPreset& preset) const;
  /// Everything applyPreset sets, as one line (the preset-state script verb).
  std::string presetState() const;
  void measureVplsSeen();

  // --- frame ---
  void frame();
  void handleInput();
  void animate();
  void drawUi();
  void drawView();
  /// The active preset's description in a box of kPresetBoxHeight at the top of the view area.
  void drawPresetExplanation(float x, float width);
  void drawLeftPanel();
  void drawRightPanel();
  void takeScreenshot(const std::string& path);

  // --- script ---
  void scriptStep();
  void execute(const ScriptCommand& c);
  [[noreturn]] void scriptFail(const ScriptCommand& c, const std::string& message);

  WorkCounters counters() const;

  EditorOptions options_;
  GLFWwindow* window_ = nullptr;

  Scene scene_;
  Camera sceneCamera_;
  std::unique_ptr<OfflineScene> offline_;  ///< over scene_, rebuilt when its geometry or lights change
  std::vector<glm::vec3> lightOffsets_;
  std::vector<float> lightScales_;

  Settings settings_;
  Method offlineMethod_ = Method::Reference;
  Staleness stale_ = Staleness::all();
  VplSet vpls_;
  int vplGenerations_ = 0;
  bool vslRadiiStale_ = false;
  double clampEnergyRemoved_ = -1.0;
  bool clampEnergyStale_ = true;

  std::unique_ptr<PreviewRenderer> preview_;
  PreviewTimings timings_;
  PreviewTimings lastPassMs_;  // most recent non-zero time of each pass: the cost of a full frame
  ChangeTimer changeTimer_;    // what the last change cost, end to end
  Image previewLinear_;
  Image residual_;
  std::string previewError_;

  OfflineJob job_;
  Image offlineImage_;
  Method offlineImageMethod_ = Method::Reference;
  bool offlineStale_ = false;
  double offlineSeconds_ = 0.0;
  double offlineClampEnergy_ = 0.0;
  std::map<std::string, OfflineTimeEstimate> offlineEstimates_;  ///< per scene file: throughput of its last renders
  Settings offlineJobSettings_;     ///< what the running (or last) offline job renders
  std::size_t offlineJobVpls_ = 0;

  CameraController camera_;
  ViewMode view_ = ViewMode::Preview;
  float divider_ = 0.5f;
  bool draggingDivider_ = false;
  bool relativeDifference_ = true;
  bool showRejected_ = false;
  DisplayTexture texture_;
  bool displayDirty_ = true;
  float viewRect_[4] = {0, 0, 0, 0};  // x, y, w, h in window pixels
  float viewScale_ = 1.0f;
  bool fitPreview_ = true;  ///< EditorOptions::fitPreview
  float previewScale_ = 0.4f;  ///< EditorOptions::previewScale
  std::string displayNote_;
  /// Non-empty when the view has nothing to show because an offline result is missing or of another size: the view
  /// then shows this message with the render buttons instead of an image.
  std::string emptyState_;

  std::vector<ChartPoint> chart_;
  bool chartPending_ = false;
  bool chartWindowOpen_ = false;  ///< the chart is shown enlarged in its own window

  std::vector<std::string> recent_;
  std::string pathInput_;
  std::string sceneError_;
  std::string settingsPath_ = "vplab-settings.json";
  std::string exportPath_ = "vplab-view.png";
  std::string ioMessage_;
  bool showHelp_ = false;
  int selectedLight_ = 0;

  bool animateLight_ = false;
  bool reseedEveryFrame_ = false;
  float animationPhase_ = 0.0f;
  const TeachingPreset* activePreset_ = nullptr;  ///< shown with the view until closed or another scene is opened
  PresetOffline pendingOffline_ = PresetOffline::None;  ///< started once the preset's VPLs exist
  std::vector<bool> vplSeen_;  ///< per VPL: does the camera see it (vpl_overlay.h); the VPL view's filled dots
  bool vplSeenStale_ = true;

  // Frame timing: the UI's share is ImGui's CPU work plus its draw submission.
  double frameMs_ = 0.0, uiMs_ = 0.0;

  // Script state.
  std::vector<ScriptCommand> script_;
  std::size_t scriptIndex_ = 0;
  int framesPending_ = 0;
  /// The preview's work is split across frames of at most about this much (plus the pass that crosses it).
  static constexpr double kPreviewFrameBudgetMs = 60.0;
  bool previewUpdating_ = false;
  /// What the update under way renders (the editor's settings and camera when it started), when it started (s), what
  /// the last finished one took from its start to its image (ms), and how many have finished.
  Settings updateSettings_;
  Camera updateCamera_;
  double updateStart_ = 0.0, lastUpdateMs_ = 0.0;
  int updatesFinished_ = 0;
  /// The preview invalidation a light edit asks for, applied when the next update starts.
  LightEdit pendingPreviewInvalidation_ = LightEdit::None;
  float previewProgress_ = 1.0f;
  bool waitingOffline_ = false;
  std::string pendingScreenshot_;
  WorkCounters mark_;
  int timingFrames_ = 0, timingTotal_ = 0;
  /// time-frames: each frame's time (ms), the light dragged (-1: the camera orbits), updates finished before.
  std::vector<double> timingFrameMs_;
  int timingLight_ = -1, timingUpdates_ = 0;
  double timingFrameSum_ = 0.0, timingUiSum_ = 0.0, timingPreviewSum_ = 0.0;
  bool finalScreenshotQueued_ = false;
  int exitCode_ = 0;
  bool quit_ = false;
};

// ------------------------------------------------------------------------------------------------------------------

Editor::Editor(const EditorOptions& options)
    : options_(options),
      settings_(options.settings),
      fitPreview_(options.fitPreview),
      previewScale_(options.previewScale) {
  if (!options.scriptPath.empty()) script_ = loadScript(options.scriptPath);  // typos fail before the window opens
  // A screenshot without a script is a script of its own: render, capture, exit.
  if (options.scriptPath.empty() && !options.screenshotPath.empty()) script_.push_back({0, "frames", {"1"}});
  requireValidSettings(settings_);
  // The scene first: a bad file fails before a window is opened.
  scene_ = loadScene(options.scenePath);
  stageScene(scene_, settings_.stage);
  applyLightsSidecar(scene_);
  sceneCamera_ = scene_.camera;

  glfwSetErrorCallback([](int code, const char* text) { std::fprintf(stderr, "GLFW error %d: %s\n", code, text); });
  if (!glfwInit())
    throw std::runtime_error("cannot open a window (no display? $DISPLAY is " +
                             std::string(std::getenv("DISPLAY") ? std::getenv("DISPLAY") : "unset") +
                             "); run under xvfb-run or use the headless commands");
  // The preview needs GL 4.5 core (DSA, SSBOs); ImGui's backend is happy with any core 3.2+.
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  window_ = glfwCreateWindow(options.windowWidth, options.windowHeight, "vplab edit", nullptr, nullptr);
  if (!window_) {
    glfwTerminate();
    throw std::runtime_error("cannot create a window with an OpenGL 4.5 core context");
  }
  glfwMakeContextCurrent(window_);
  keepGlDriversLoaded();
  // Load every gl* through the window system's own getProcAddress, never libGL's exported symbols.
  if (!gladLoadGL(glfwGetProcAddress)) throw std::runtime_error("cannot load OpenGL functions through GLFW");
  glfwSwapInterval(script_.empty() ? 1 : 0);
  glfwSetWindowUserPointer(window_, this);
  glfwSetDropCallback(window_, [](GLFWwindow* w, int count, const char** paths) {
    auto* editor = static_cast<Editor*>(glfwGetWindowUserPointer(w));
    if (count > 0) editor->openScene(paths[0]);
  });

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // fixed layout: nothing to remember between runs
  ImGui::StyleColorsDark();
  // The panels get their colour from the framebuffer clear (kBackground), not from a blended background quad: under
  // llvmpipe every blended fragment counts, and the two panels cover more than half of the window (the UI's raster
  // time at 1280x720 falls from about 7.5 to 4 ms).
  ImGui::GetStyle().Colors[ImGuiCol_WindowBg].w = 0.0f;
  ImGui_ImplGlfw_InitForOpenGL(window_, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");

  preview_ = std::make_unique<PreviewRenderer>();

  if (std::ifstream in(recentFilesPath()); in)
    for (std::string line; std::getline(in, line);)
      if (!line.empty()) recent_.push_back(line);

  rebuildAcceleration();
  camera_ = CameraController(sceneCamera_, glm::length(scene_.bounds.center() - sceneCamera_.position),
                             scene_.bounds.diagonal());
  pathInput_ = options.scenePath;
  if (script_.empty()) {
    recent_.erase(std::remove(recent_.begin(), recent_.end(), options.scenePath), recent_.end());
    recent_.insert(recent_.begin(), options.scenePath);
  }
  // UI windows are hidden on their first frame (ImGui lays a window out before it shows it): scripts start after two.
  framesPending_ = script_.empty() ? 0 : 2;
}

Editor::~Editor() {
  job_.cancel();
  preview_.reset();
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  if (window_) glfwDestroyWindow(window_);
  glfwTerminate();
  if (script_.empty() && !recentFilesPath().empty()) {
    // Best effort at exit: a list that cannot be saved is not worth an error, but it is never left cut.
    std::string text;
    for (std::size_t i = 0; i < recent_.size() && i < 10; ++i) text += recent_[i] + "\n";
    try {
      writeFileAtomically(recentFilesPath(), text);
    } catch (const FileWriteError& e) {
      std::fprintf(stderr, "vplab edit: %s\n", e.what());
    }
  }
}

WorkCounters Editor::counters() const {
  return {vplGenerations_, preview_->counters().vplShadowMaps, preview_->counters().gather};
}

// --- scene and lights ---------------------------------------------------------------------------------------------

bool Editor::openScene(const std::string& path, bool /*keepSettingsSize*/) {
  Scene loaded;
  try {
    loaded = loadScene(path);
    stageScene(loaded, settings_.stage);
    applyLightsSidecar(loaded);
  } catch (const std::exception& e) {
    // A bad file leaves the current scene in place.
    sceneError_ = e.what();
    return false;
  }
  sceneError_.clear();
  job_.cancel();
  activePreset_ = nullptr;  // a preset that wants it sets itself again after this
  pendingOffline_ = PresetOffline::None;
  scene_ = std::move(loaded);
  sceneCamera_ = scene_.camera;
  rebuildAcceleration();
  camera_ = CameraController(sceneCamera_, glm::length(scene_.bounds.center() - sceneCamera_.position),
                             scene_.bounds.diagonal());
  lightOffsets_.clear();
  lightScales_.clear();
  // An update of the old scene is abandoned: the next one starts from scratch.
  preview_->invalidateScene();
  previewUpdating_ = false;
  pendingPreviewInvalidation_ = LightEdit::None;
  markStale(Staleness::all());
  offlineImage_ = Image();
  chart_.clear();
  pathInput_ = path;
  recent_.erase(std::remove(recent_.begin(), recent_.end(), path), recent_.end());
  recent_.insert(recent_.begin(), path);
  return true;
}

void Editor::rebuildAcceleration() {
  offline_.reset();
  offline_ = std::make_unique<OfflineScene>(scene_);
}

void Editor::editLight(std::size_t index, const glm::vec3& offset, float scale) {
  std::vector<LightHandle> lights = editableLights(scene_);
  if (index >= lights.size()) throw std::out_of_range("no light " + std::to_string(index));
  lightOffsets_.resize(lights.size(), glm::vec3(0.0f));
  lightScales_.resize(lights.size(), 1.0f);
  LightEdit edit = LightEdit::None;
  if (offset != glm::vec3(0.0f)) edit = combine(edit, moveLight(scene_, lights[index], offset));
  if (scale != 1.0f) edit = combine(edit, scaleLight(scene_, lights[index], scale));
  lightOffsets_[index] += offset;
  lightScales_[index] *= scale;
  applyLightEdit(edit);
}

void Editor::applyLightEdit(LightEdit edit) {
  if (edit == LightEdit::None) return;
  // A punctual light keeps the geometry: the BVH, the GL scene and the VPL point set stay.
  if (edit == LightEdit::Geometry) {
    rebuildAcceleration();
    pendingPreviewInvalidation_ = LightEdit::Geometry;
  } else {
    offline_->punctualLightsChanged();
    pendingPreviewInvalidation_ = combine(pendingPreviewInvalidation_, LightEdit::Punctual);
  }
  markStale(staleAfterLightEdit());
}

// --- work ---------------------------------------------------------------------------------------------------------

void Editor::markStale(const Staleness& s) {
  if (s.anyPreview()) changeTimer_.changed(now());
  stale_ |= s;
  if (s.offline && !offlineImage_.empty()) offlineStale_ = true;
  if (s.vpls || s.gather) clampEnergyStale_ = true;
  if (s.vpls || s.gather) vplSeenStale_ = true;  // gather: the camera may have moved
  displayDirty_ = true;
}

void Editor::changeSettings(const Settings& next) {
  if (!validateSettings(next).empty()) return;
  Staleness s = staleAfterSettingsChange(settings_, next, offlineMethod_);
  if (!s.vpls && (next.vslRadius != settings_.vslRadius || next.vslRadiusFromDensity != settings_.vslRadiusFromDensity))
    vslRadiiStale_ = true;
  settings_ = next;
  markStale(s);
  if (s.anyPreview()) chartPending_ = true;
}

void Editor::regenerateVpls() {
  // Importance-driven generation (rejection, bidirectional, Metropolis) measures importance from the current view.
  scene_.camera = camera_.camera();
  vpls_ = generateVpls(*offline_, settings_);
  changeTimer_.vplsGenerated(vpls_.stats.generationSeconds * 1e3);
  ++vplGenerations_;
  vslRadiiStale_ = false;
  preview_->invalidateVpls();
}

void Editor::measureClampEnergy() {
  clampEnergyStale_ = false;
  if (std::isinf(settings_.clampBound) || vpls_.vpls.empty()) {
    clampEnergyRemoved_ = 0.0;
    return;
  }
  // Energy removed by G_b over camera-visible points: sum(unclamped - clamped) / sum(unclamped) of the luminance of
  // every visible VPL contribution (docs/theory.md §4). A few hundred points suffice for a percentage.
  Settings pointSettings = settings_;
  pointSettings.importancePoints = std::max(16, std::min(256, 65536 / static_cast<int>(vpls_.vpls.size() + 1)));
  scene_.camera = camera_.camera();
  std::vector<ShadingPoint> points = importancePoints(*offline_, pointSettings);
  const EmbreeScene& embree = offline_->embree();
  double clamped = 0.0, unclamped = 0.0;
  for (const ShadingPoint& sp : points)
    for (const Vpl& vpl : vpls_.vpls) {
      glm::vec3 full;
      glm::vec3 c =
          vplUnoccludedContribution(sp, vpl, brdfParamsAt(scene_, vpl.material, vpl.uv), settings_.clampBound, &full);
      if (luminance(full) <= 0.0f) continue;
      if (!embree.visible(sp.hit.position, sp.hit.geometricNormal, vpl.position, vpl.geometricNormal)) continue;
      clamped += luminance(c);
      unclamped += luminance(full);
    }
  clampEnergyRemoved_ = unclamped > 0.0 ? (unclamped - clamped) / unclamped : 0.0;
}

void Editor::measureVplsSeen() {
  vplSeenStale_ = false;
  vplSeen_ = vplsSeenByCamera(offline_->embree(), camera_.camera(), vpls_.vpls);
}

void Editor::updateWork() {
  // Changes made while an update is under way wait for it (their flags stay in stale_): every finished image is the
  // one `vplab preview` gives for the settings, camera and VPLs its update started with, and a light drag or an orbit
  // shows a new image each time an update finishes instead of restarting the update every frame.
  const bool startUpdate = !previewUpdating_ && stale_.anyPreview();
  if (!previewUpdating_) {
    if (stale_.vpls) regenerateVpls();
    if (vslRadiiStale_) {
      std::vector<float> radii = vslRadii(vpls_.vpls, settings_, scene_.bounds.diagonal());
      for (std::size_t i = 0; i < radii.size(); ++i) vpls_.vpls[i].radius = radii[i];
      preview_->invalidateVpls();
      vslRadiiStale_ = false;
    }
    if (clampEnergyStale_) measureClampEnergy();
  }
  if (!previewUpdating_ && view_ == ViewMode::VplOverlay && vplSeenStale_) measureVplsSeen();
  if (pendingOffline_ != PresetOffline::None) {
    startOffline(pendingOffline_ == PresetOffline::Reference);
    pendingOffline_ = PresetOffline::None;
  }
  if (startUpdate) {
    if (pendingPreviewInvalidation_ == LightEdit::Geometry) preview_->invalidateScene();
    if (pendingPreviewInvalidation_ == LightEdit::Punctual) preview_->invalidateLights();
    pendingPreviewInvalidation_ = LightEdit::None;
    updateSettings_ = settings_;
    updateCamera_ = camera_.camera();
    updateStart_ = now();
  }
  if (startUpdate || previewUpdating_) {
    try {
      // Long work is split across frames (PreviewRenderer::render's budget): the last finished image stays on screen
      // with "updating n %" until the new one is complete, which is then the image `vplab preview` gives.
      timings_ = preview_->render(scene_, vpls_, updateSettings_, updateCamera_, kPreviewFrameBudgetMs);
      changeTimer_.rendered(now(), timings_);
      previewUpdating_ = !timings_.complete;
      previewProgress_ = timings_.progress;
      if (timings_.complete) {
        previewLinear_ = preview_->readLinear();
        residual_ = view_ == ViewMode::SsbcResidual ? preview_->readLinear(PreviewOutput::Residual) : Image();
        lastUpdateMs_ = (now() - updateStart_) * 1e3;
        ++updatesFinished_;
      }
      previewError_.clear();
    } catch (const std::exception& e) {
      // A shader that fails to reload, or settings the GL context cannot hold, keep the last image; the message is
      // shown in the view.
      previewError_ = e.what();
      previewUpdating_ = false;
    }
    auto keep = [](double& last, double now) {
      if (now > 0.0) last = now;
    };
    keep(lastPassMs_.gbufferMs, timings_.gbufferMs);
    keep(lastPassMs_.directShadowMs, timings_.directShadowMs);
    keep(lastPassMs_.directMs, timings_.directMs);
    keep(lastPassMs_.vplShadowMs, timings_.vplShadowMs);
    keep(lastPassMs_.gatherMs, timings_.gatherMs);
    keep(lastPassMs_.ssbcMs, timings_.ssbcMs);
    keep(lastPassMs_.tonemapMs, timings_.tonemapMs);
    if (startUpdate) {
      bool offline = stale_.offline;
      stale_ = Staleness{};
      stale_.offline = offline;
    }
    if (!previewUpdating_) {
      displayDirty_ = true;
      if (chartPending_) addChartPoint();
    }
  }
  if (displayDirty_) composeDisplay();
}

void Editor::finishWork() {
  do updateWork();
  while ((previewUpdating_ || stale_.anyPreview()) && previewError_.empty());
}

void Editor::addChartPoint() {
  // A point needs a reference that matches the current scene, camera and image size.
  if (offlineImage_.empty() || offlineStale_ || offlineImageMethod_ != Method::Reference || job_.running() ||
      previewLinear_.width != offlineImage_.width || previewLinear_.height != offlineImage_.height)
    return;
  chartPending_ = false;
  ChartPoint p;
  p.frameMs = lastPassMs_.totalMs();
  p.relMse = compareImages(previewLinear_, offlineImage_).relMse;
  // The settings of the image shown: a change made since waits for the next update.
  p.settings = updateSettings_;
  p.label = describeSettings(updateSettings_);
  for (ChartPoint& q : chart_)
    if (settingsToJson(q.settings) == settingsToJson(p.settings)) {
      q = p;
      return;
    }
  chart_.push_back(p);
}

std::string Editor::offlineMismatch(const std::string& what) const {
  if (offlineImage_.empty()) return "No offline result yet.\n" + what;
  return "The offline result is " + std::to_string(offlineImage_.width) + "x" + std::to_string(offlineImage_.height) +
         ", the preview " + std::to_string(previewLinear_.width) + "x" + std::to_string(previewLinear_.height) +
         ": render it again at this size.\n" + what;
}

void Editor::composeDisplay() {
  displayDirty_ = false;
  displayNote_.clear();
  emptyState_.clear();
  const Image& preview = view_ == ViewMode::SsbcResidual ? residual_ : previewLinear_;
  const bool haveOffline = !offlineImage_.empty();
  const bool sameSize =
      haveOffline && offlineImage_.width == previewLinear_.width && offlineImage_.height == previewLinear_.height;
  switch (view_) {
    case ViewMode::Preview:
    case ViewMode::VplOverlay:
    case ViewMode::SsbcResidual: {
      if (preview.empty()) {
        displayNote_ = view_ == ViewMode::SsbcResidual && settings_.ssbcSteps == 0 ? "SSBC is off (steps = 0)"
                                                                                   : "no preview image";
        if (preview.empty()) return;
      }
      texture_.upload(preview.width, preview.height, tonemapToRgb8(preview, settings_.exposure));
      return;
    }
    case ViewMode::Reference: {
      if (!haveOffline) {
        emptyState_ = "No offline result yet.\nThe reference view shows the path-traced reference or the exact VPL "
                      "render of the current scene, camera and settings.";
        return;
      }
      texture_.upload(offlineImage_.width, offlineImage_.height, tonemapToRgb8(offlineImage_, settings_.exposure));
      return;
    }
    case ViewMode::Split: {
      if (!sameSize) {
        emptyState_ = offlineMismatch("The split view puts the preview left of the divider and the offline result "
                                      "right of it.");
        return;
      }
      std::vector<uint8_t> left = tonemapToRgb8(previewLinear_, settings_.exposure);
      std::vector<uint8_t> right = tonemapToRgb8(offlineImage_, settings_.exposure);
      const int w = previewLinear_.width;
      const int split = std::clamp(static_cast<int>(divider_ * w), 0, w);
      for (int y = 0; y < previewLinear_.height; ++y)
        for (int x = split; x < w; ++x)
          for (int c = 0; c < 3; ++c) left[(static_cast<std::size_t>(y) * w + x) * 3 + c] = right[(y * w + x) * 3 + c];
      texture_.upload(w, previewLinear_.height, left);
      return;
    }
    case ViewMode::Difference: {
      if (!sameSize) {
        emptyState_ = offlineMismatch("The difference view maps the preview's error against the offline result.");
        return;
      }
      HeatmapOptions options;
      if (relativeDifference_) {
        options.colormap = Colormap::Viridis;
        options.title = "relative error vs offline";  // short: the legend is 256 px wide
        Heatmap h = renderHeatmap(relativeErrorImage(previewLinear_, offlineImage_), options);
        texture_.upload(h.width, h.height, h.rgb);
      } else {
        options.colormap = Colormap::Diverging;
        options.title = "preview - offline";
        Heatmap h = renderHeatmap(signedDifferenceImage(previewLinear_, offlineImage_), options);
        texture_.upload(h.width, h.height, h.rgb);
      }
      return;
    }
  }
}

void Editor::startOffline(bool reference) {
  offlineMethod_ = reference ? Method::Reference : exactCounterpartOf(settings_);
  job_.start(scene_, camera_.camera(), vpls_, settings_, offlineMethod_);
  offlineJobSettings_ = settings_;
  offlineJobVpls_ = vpls_.vpls.size();
  offlineStale_ = false;
}

void Editor::pollOffline() {
  if (std::optional<Image> image = job_.takeImage()) {
    offlineImage_ = std::move(*image);
    offlineImageMethod_ = job_.method();
    displayDirty_ = view_ != ViewMode::Preview && view_ != ViewMode::VplOverlay && view_ != ViewMode::SsbcResidual;
  }
  if (job_.takeFinished()) {
    offlineSeconds_ = job_.seconds();
    offlineClampEnergy_ = job_.clampEnergyRemoved();
    if (!job_.cancelled() && job_.error().empty())
      offlineEstimates_[scene_.sourcePath].record(job_.method(), offlineRenderSettings(offlineJobSettings_, job_.method()),
                                                  offlineJobVpls_, job_.seconds());
    if (!job_.cancelled() && job_.error().empty() && job_.method() == Method::Reference) {
      // A new reference: the chart's errors were measured against the old one.
      chart_.clear();
      chartPending_ = true;
      addChartPoint();
    }
    displayDirty_ = true;
  }
}

Settings Editor::presetSettingsHere(const TeachingPreset& preset) const {
  Settings s = preset.settings;
  s.threads = settings_.threads;  // the machine's, not the lesson's
  if (fitPreview_) {
    // The fitted preview takes the size the view gives it with the preset's explanation above.
    const glm::ivec2 size = fittedPreviewSize(true);
    s.width = size.x;
    s.height = size.y;
  }
  return s;
}

bool Editor::applyPreset(const TeachingPreset& preset) {
  // Always reloaded, even when it is the current scene: a previous preset (or the user) may have moved or scaled
  // lights, and openScene also resets the camera and drops the offline result and the chart.
  if (!openScene(std::string(VPLAB_ASSET_DIR) + "/scenes/" + preset.scene)) return false;
  changeSettings(presetSettingsHere(preset));
  view_ = preset.view;
  if (view_ == ViewMode::SsbcResidual) stale_.gather = true;
  relativeDifference_ = !preset.signedDifference;
  showRejected_ = preset.showRejected;
  divider_ = 0.5f;
  animateLight_ = preset.animateLight;
  reseedEveryFrame_ = preset.reseedEveryFrame;
  animationPhase_ = 0.0f;
  pendingOffline_ = preset.offline;
  activePreset_ = &preset;
  displayDirty_ = true;
  return true;
}

std::string Editor::presetState() const {
  // Hashes keep the line short; each part is named so that a difference says what leaked.
  auto hash = [](const std::string& text) {
    uint64_t h = 1469598103934665603ull;  // FNV-1a
    for (unsigned char c : text) h = (h ^ c) * 1099511628211ull;
    char out[17];
    std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(h));
    return std::string(out);
  };
  auto vec = [](const glm::vec3& v) {
    char out[96];
    std::snprintf(out, sizeof out, "%.9g %.9g %.9g;", v.x, v.y, v.z);
    return std::string(out);
  };
  std::string lights;
  for (const PunctualLight& l : scene_.punctualLights) lights += vec(l.position) + vec(l.direction) + vec(l.intensity);
  for (const Material& m : scene_.materials) lights += vec(m.emission);
  for (uint32_t t : scene_.emissiveTriangles)
    for (int k = 0; k < 3; ++k) lights += vec(scene_.positions[scene_.triangles[t][k]]);
  const Camera cam = camera_.camera();
  char view[160];
  std::snprintf(view, sizeof view, "%s relative=%d rejected=%d divider=%g animate=%d reseed=%d phase=%g",
                toString(view_), relativeDifference_, showRejected_, divider_, animateLight_, reseedEveryFrame_,
                animationPhase_);
  return "scene=" + std::filesystem::path(scene_.sourcePath).filename().string() +
         " settings=" + hash(settingsToJson(settings_)) + " lights=" + hash(lights) +
         " camera=" + hash(vec(cam.position) + vec(cam.forward) + vec(cam.up) + std::to_string(cam.yfov)) + " " +
         view;
}

// --- frame --------------------------------------------------------------------------------------------------------

void Editor::handleInput() {
  ImGuiIO& io = ImGui::GetIO();
  bool cameraMoved = false;
  if (!io.WantCaptureMouse) {
    const ImVec2 delta = io.MouseDelta;
    const float radiansPerPixel = 0.005f;
    const float divX = viewRect_[0] + divider_ * viewRect_[2];
    if (view_ == ViewMode::Split && io.MouseClicked[0] && std::abs(io.MousePos.x - divX) < 6.0f)
      draggingDivider_ = true;
    if (!io.MouseDown[0]) draggingDivider_ = false;
    if (draggingDivider_) {
      divider_ = std::clamp((io.MousePos.x - viewRect_[0]) / std::max(viewRect_[2], 1.0f), 0.0f, 1.0f);
      displayDirty_ = true;
    } else if (io.MouseDown[0] && (delta.x != 0.0f || delta.y != 0.0f)) {
      camera_.orbit(-delta.x * radiansPerPixel, -delta.y * radiansPerPixel);
      cameraMoved = true;
    } else if ((io.MouseDown[1] || io.MouseDown[2]) && (delta.x != 0.0f || delta.y != 0.0f)) {
      camera_.pan(-delta.x * 0.002f, delta.y * 0.002f);
      cameraMoved = true;
    }
    if (io.MouseWheel != 0.0f) {
      camera_.zoom(io.MouseWheel);
      cameraMoved = true;
    }
  }
  if (!io.WantCaptureKeyboard) {
    const float step = 0.5f * io.DeltaTime;  // scene diagonals per second
    glm::vec3 fly(0.0f);
    if (ImGui::IsKeyDown(GLFW_KEY_W)) fly.x += step;
    if (ImGui::IsKeyDown(GLFW_KEY_S)) fly.x -= step;
    if (ImGui::IsKeyDown(GLFW_KEY_D)) fly.y += step;
    if (ImGui::IsKeyDown(GLFW_KEY_A)) fly.y -= step;
    if (ImGui::IsKeyDown(GLFW_KEY_E)) fly.z += step;
    if (ImGui::IsKeyDown(GLFW_KEY_Q)) fly.z -= step;
    if (fly != glm::vec3(0.0f)) {
      camera_.fly(fly.x, fly.y, fly.z);
      cameraMoved = true;
    }
    if (ImGui::IsKeyPressed(GLFW_KEY_F)) {
      camera_ = CameraController(sceneCamera_, glm::length(scene_.bounds.center() - sceneCamera_.position),
                                 scene_.bounds.diagonal());
      cameraMoved = true;
    }
    for (int i = 0; i < 6; ++i)
      if (ImGui::IsKeyPressed(GLFW_KEY_1 + i)) {
        view_ = kAllViewModes[i];
        markStale({});
        if (view_ == ViewMode::SsbcResidual) stale_.gather = true;
      }
    if (ImGui::IsKeyPressed(GLFW_KEY_O) && !job_.running()) startOffline(true);
    if (ImGui::IsKeyPressed(GLFW_KEY_ESCAPE)) job_.cancel();
    if (ImGui::IsKeyPressed(GLFW_KEY_H) || ImGui::IsKeyPressed(GLFW_KEY_F1)) showHelp_ = !showHelp_;
  }
  if (cameraMoved) markStale(staleAfterCameraMove());
}

void Editor::animate() {
  if (!animateLight_) return;
  std::vector<LightHandle> lights = editableLights(scene_);
  if (lights.empty()) return;
  const glm::vec3 offset = lightAnimationStep(animationPhase_, scene_.bounds.diagonal());
  if (reseedEveryFrame_) {
    Settings next = settings_;
    next.seed = settings_.seed + 1;
    changeSettings(next);
  }
  editLight(0, offset, 1.0f);
}

void Editor::frame() {
  const double start = now();
  const bool busy = stale_.anyPreview() || job_.running() || animateLight_ || !script_.empty();
  if (busy)
    glfwPollEvents();
  else
    glfwWaitEventsTimeout(0.1);  // idle: do not spin two shared cores for an unchanged picture

  if (!script_.empty()) scriptStep();
  if (quit_) return;
  animate();
  pollOffline();

  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  const double uiStart = now();
  ImGui::NewFrame();
  handleInput();
  const double uiPause = now();
  updateWork();
  glFinish();
  const double previewEnd = now();
  drawUi();
  ImGui::Render();
  int width, height;
  glfwGetFramebufferSize(window_, &width, &height);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, width, height);
  glClearColor(kBackground[0], kBackground[1], kBackground[2], 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  glFinish();
  // Showing the image is part of the preview's time, like its readback and upload; the UI draws over it.
  const double viewStart = now();
  if (texture_.valid() && emptyState_.empty()) {
    // viewRect_ is in ImGui's window coordinates; the framebuffer may have more pixels (HiDPI).
    const ImVec2 fb = ImGui::GetIO().DisplayFramebufferScale;
    texture_.blitTo(viewRect_[0] * fb.x, viewRect_[1] * fb.y, viewRect_[2] * fb.x, viewRect_[3] * fb.y, height,
                    viewScale_ != std::floor(viewScale_));
  }
  glFinish();
  const double viewEnd = now();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  glFinish();
  const double uiEnd = now();
  // A screenshot shows a finished image; an animated light never lets the image finish, so it takes the frame as is.
  if (!pendingScreenshot_.empty() &&
      ((!previewUpdating_ && !stale_.anyPreview()) || animateLight_ || !previewError_.empty())) {
    takeScreenshot(pendingScreenshot_);
    pendingScreenshot_.clear();
  }
  glfwSwapBuffers(window_);
  frameMs_ = (now() - start) * 1e3;
  uiMs_ = ((uiPause - uiStart) + (viewStart - previewEnd) + (uiEnd - viewEnd)) * 1e3;
  if (timingFrames_ > 0) {
    timingFrameMs_.push_back(frameMs_);
    timingFrameSum_ += frameMs_;
    timingUiSum_ += uiMs_;
    timingPreviewSum_ += ((previewEnd - uiPause) + (viewEnd - viewStart)) * 1e3;
    if (--timingFrames_ == 0) {
      double n = timingTotal_;
      std::vector<double> sorted = timingFrameMs_;
      std::sort(sorted.begin(), sorted.end());
      auto quantile = [&](double q) { return sorted[std::min(sorted.size() - 1, static_cast<std::size_t>(q * sorted.size()))]; };
      std::printf(
          "frame-time frames=%d size=%dx%d window=%dx%d frame_ms=%.2f p50_ms=%.2f p95_ms=%.2f max_ms=%.2f "
          "preview_ms=%.2f ui_ms=%.2f ui_share=%.1f%% updates=%d last_update_ms=%.1f while=%s\n",
          timingTotal_, settings_.width, settings_.height, width, height, timingFrameSum_ / n, quantile(0.5),
          quantile(0.95), sorted.back(), timingPreviewSum_ / n, timingUiSum_ / n,
          100.0 * timingUiSum_ / timingFrameSum_, updatesFinished_ - timingUpdates_, lastUpdateMs_,
          timingLight_ >= 0 ? "light-drag" : "orbit");
      std::fflush(stdout);
    }
  }
}

void Editor::takeScreenshot(const std::string& path) {
  int width, height;
  glfwGetFramebufferSize(window_, &width, &height);
  std::vector<uint8_t> pixels(static_cast<std::size_t>(width) * height * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, pixels.data());
  // GL's rows start at the bottom; PNG's at the top.
  std::vector<uint8_t> flipped(pixels.size());
  const std::size_t row = static_cast<std::size_t>(width) * 3;
  for (int y = 0; y < height; ++y)
    std::copy_n(pixels.data() + static_cast<std::size_t>(height - 1 - y) * row, row, flipped.data() + y * row);
  writePngRgb8(path, width, height, flipped);
  std::printf("screenshot %s window %dx%d view %d %d %d %d scale %g\n", path.c_str(), width, height,
              static_cast<int>(viewRect_[0]), static_cast<int>(viewRect_[1]), static_cast<int>(viewRect_[2]),
              static_cast<int>(viewRect_[3]), viewScale_);
  std::fflush(stdout);
}

int Editor::run() {
  while (!quit_ && !glfwWindowShouldClose(window_)) frame();
  return exitCode_;
}

// --- UI -----------------------------------------------------------------------------------------------------------

void Editor::drawView() {
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  const float areaX = kLeftPanelWidth, areaW = display.x - kLeftPanelWidth - kRightPanelWidth;
  // The active preset's explanation sits above the image, which fits in what is left.
  const float areaY = activePreset_ ? kPresetBoxHeight : 0.0f, areaH = display.y - areaY;
  ImDrawList* draw = ImGui::GetBackgroundDrawList();
  if (activePreset_) drawPresetExplanation(areaX, areaW);
  if (fitPreview_) {
    const glm::ivec2 size = fittedPreviewSize(activePreset_ != nullptr);
    if (size.x != settings_.width || size.y != settings_.height) {
      Settings next = settings_;
      next.width = size.x;
      next.height = size.y;
      changeSettings(next);
    }
  }
  if (!displayNote_.empty() || !previewError_.empty()) {
    std::string note = previewError_.empty() ? displayNote_ : "preview error: " + previewError_;
    draw->AddText(ImVec2(areaX + 12, areaY + 12), IM_COL32(230, 200, 120, 255), note.c_str());
  }
  if (!emptyState_.empty() || !texture_.valid()) {
    if (!emptyState_.empty()) drawEmptyState(areaX, areaY, areaW, areaH);
    drawStatusBar(areaX + 8.0f, areaY + areaH - 20.0f);
    return;
  }
  const float w = static_cast<float>(texture_.width()), h = static_cast<float>(texture_.height());
  // A fitted preview fills the view (linear filtering); an explicit size is shown at integer zoom, which keeps
  // preview pixels square and exact (the tests compare them with the headless preview).
  float scale = std::min((areaW - 16.0f) / w, (areaH - 40.0f) / h);
  if (!fitPreview_ && scale >= 1.0f) scale = std::floor(scale);
  viewScale_ = scale;
  const float x0 = std::floor(areaX + 0.5f * (areaW - w * scale));
  const float y0 = std::floor(areaY + 0.5f * (areaH - h * scale));
  viewRect_[0] = x0;
  viewRect_[1] = y0;
  viewRect_[2] = w * scale;
  viewRect_[3] = h * scale;
  // The image itself is blitted before ImGui draws (frame()); the overlays below go on top of it.
  if (view_ == ViewMode::Split && displayNote_.empty()) {
    float x = x0 + divider_ * w * scale;
    draw->AddLine(ImVec2(x, y0), ImVec2(x, y0 + h * scale), IM_COL32(255, 255, 255, 200), 1.0f);
    draw->AddText(ImVec2(x0 + 4, y0 + 4), IM_COL32(255, 255, 255, 220), "preview");
    std::string right = std::string(toString(offlineImageMethod_)) + (offlineStale_ ? " (stale)" : "");
    draw->AddText(ImVec2(x0 + w * scale - 8 - 7.0f * right.size(), y0 + 4), IM_COL32(255, 255, 255, 220),
                  right.c_str());
  }
  if (view_ == ViewMode::VplOverlay) {
    const Camera cam = camera_.camera();
    const float aspect = static_cast<float>(settings_.width) / static_cast<float>(settings_.height);
    const float tanHalf = std::tan(0.5f * cam.yfov);
    auto project = [&](const glm::vec3& p, ImVec2& out) {
      glm::vec3 d = p - cam.position;
      float z = glm::dot(d, cam.forward);
      if (z <= cam.znear) return false;
      float x = glm::dot(d, cam.right()) / (z * tanHalf * aspect);
      float y = glm::dot(d, cam.up) / (z * tanHalf);
      out = ImVec2(x0 + 0.5f * (x + 1.0f) * w * scale, y0 + 0.5f * (1.0f - y) * h * scale);
      return std::abs(x) <= 1.0f && std::abs(y) <= 1.0f;
    };
    float maxFlux = 1e-12f;
    for (const Vpl& v : vpls_.vpls) maxFlux = std::max(maxFlux, luminance(v.flux));
    // The ring takes the generation method's chart colour (the one its bench rows have), so a screenshot says which
    // method put the VPLs there.
    const unsigned rgb = benchMethodColourRgb(generationVariantOf(settings_).name);
    const ImU32 ring = IM_COL32((rgb >> 16) & 0xff, (rgb >> 8) & 0xff, rgb & 0xff, 230);
    const bool seenKnown = vplSeen_.size() == vpls_.vpls.size();
    for (std::size_t i = 0; i < vpls_.vpls.size(); ++i) {
      const Vpl& v = vpls_.vpls[i];
      const bool lightsView = !seenKnown || vplSeen_[i];
      ImVec2 p;
      if (!project(v.position, p)) continue;
      // Size by relative power on a log scale, colour by the flux's chromaticity; a VPL the camera does not see
      // (behind a wall, in another room) is a hollow grey ring.
      float rel = std::clamp(luminance(v.flux) / maxFlux, 1e-4f, 1.0f);
      float radius = 1.5f + 4.0f * (1.0f + std::log10(rel) / 4.0f);
      glm::vec3 c = v.flux / std::max({v.flux.r, v.flux.g, v.flux.b, 1e-12f});
      if (lightsView) {
        draw->AddCircleFilled(
            p, radius,
            IM_COL32(static_cast<int>(255 * c.r), static_cast<int>(255 * c.g), static_cast<int>(255 * c.b), 230));
        draw->AddCircle(p, radius + 0.5f, ring, 0, 1.5f);
      } else {
        draw->AddCircle(p, radius, IM_COL32(160, 160, 160, 200), 0, 1.5f);
      }
    }
    if (seenKnown && !vpls_.vpls.empty()) {
      char count[160];
      std::snprintf(count, sizeof count, "the camera sees %zu of %zu VPLs (%.0f %%); hollow rings: hidden",
                    static_cast<std::size_t>(std::count(vplSeen_.begin(), vplSeen_.end(), true)), vpls_.vpls.size(),
                    100.0 * seenShare(vplSeen_));
      draw->AddText(ImVec2(x0, y0 - 18.0f), IM_COL32(230, 230, 230, 255), count);
    }
    draw->AddText(ImVec2(x0 + 4, y0 + 4), ring, generationVariantOf(settings_).label);
    if (showRejected_)
      for (const Vpl& v : vpls_.rejected) {
        ImVec2 p;
        if (!project(v.position, p)) continue;
        draw->AddLine(ImVec2(p.x - 2, p.y - 2), ImVec2(p.x + 2, p.y + 2), IM_COL32(150, 150, 150, 180));
        draw->AddLine(ImVec2(p.x - 2, p.y + 2), ImVec2(p.x + 2, p.y - 2), IM_COL32(150, 150, 150, 180));
      }
  }
  drawStatusBar(areaX + 8.0f, areaY + areaH - 20.0f);
}

void Editor::drawStatusBar(float x, float y) {
  // What a change costs is the time until its image is complete, over frames; a single frame says little.
  char change[96] = "";
  if (changeTimer_.pending())
    std::snprintf(change, sizeof change, "updating %d %%, %.0f ms so far",
                  static_cast<int>(100.0f * previewProgress_), changeTimer_.pendingMs(now()));
  else if (changeTimer_.lastMs() >= 0.0)
    std::snprintf(change, sizeof change, "last change %.0f ms (%d frame%s)", changeTimer_.lastMs(),
                  changeTimer_.lastFrames(), changeTimer_.lastFrames() == 1 ? "" : "s");
  char status[256];
  std::snprintf(status, sizeof status, "%s %dx%d  %s  this frame %.0f ms  %zu VPLs", toString(view_),
                settings_.width, settings_.height, change, frameMs_, vpls_.vpls.size());
  ImGui::GetBackgroundDrawList()->AddText(ImVec2(x, y), IM_COL32(200, 200, 200, 255), status);
}

glm::ivec2 Editor::fittedPreviewSize(bool presetBox) const {
  // The view area between the panels, less the margins drawView keeps around the image and for the status bar.
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  const float width = display.x - kLeftPanelWidth - kRightPanelWidth - 16.0f;
  const float height = display.y - (presetBox ? kPresetBoxHeight : 0.0f) - 40.0f;
  return {std::clamp(static_cast<int>(std::lround(width * previewScale_)), 16, 2048),
          std::clamp(static_cast<int>(std::lround(height * previewScale_)), 16, 2048)};
}

void Editor::drawEmptyState(float x, float y, float width, float height) {
  const float boxWidth = std::min(width - 32.0f, 420.0f);
  ImGui::SetNextWindowPos(ImVec2(x + 0.5f * width, y + 0.4f * height), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
  ImGui::SetNextWindowSize(ImVec2(boxWidth, 0.0f));
  ImGui::Begin("##empty", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings |
                   ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoFocusOnAppearing);
  ImGui::PushTextWrapPos(boxWidth - ImGui::GetStyle().WindowPadding.x);
  ImGui::TextUnformatted(emptyState_.c_str());
  ImGui::PopTextWrapPos();
  if (job_.running()) {
    ImGui::Text("%s running: %.0f %%", toString(job_.method()), 100.0f * job_.progress());
    ImGui::SameLine();
    if (ImGui::SmallButton("Cancel")) job_.cancel();
  } else {
    if (ImGui::Button("Render reference (O)")) startOffline(true);
    ImGui::SameLine();
    if (ImGui::Button("Render exact VPL")) startOffline(false);
  }
  ImGui::End();
}

void Editor::drawPresetExplanation(float x, float width) {
  const bool modified = settingsToJson(settings_) != settingsToJson(presetSettingsHere(*activePreset_));
  ImGui::SetNextWindowPos(ImVec2(x, 0.0f));
  ImGui::SetNextWindowSize(ImVec2(width, kPresetBoxHeight - 4.0f));
  ImGui::Begin("##preset", nullptr,
               ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                   ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
                   ImGuiWindowFlags_NoBringToFrontOnFocus);
  if (ImGui::SmallButton("close explanation")) activePreset_ = nullptr;
  if (modified) {
    ImGui::SameLine();
    ImGui::TextDisabled("settings changed since the preset");
  }
  if (activePreset_) ImGui::TextWrapped("%s", presetDescription(*activePreset_).c_str());
  ImGui::End();
}

void Editor::drawLeftPanel() {
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(ImVec2(kLeftPanelWidth, display.y));
  ImGui::Begin("Controls", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  ImGui::PushItemWidth(170.0f);

  if (ImGui::CollapsingHeader("Scene", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::InputText("##path", &pathInput_);
    ImGui::SameLine();
    if (ImGui::Button("Open")) openScene(pathInput_);
    if (!sceneError_.empty()) ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.4f, 1.0f), "%s", sceneError_.c_str());
    if (!recent_.empty() && ImGui::BeginCombo("recent", "recent files")) {
      for (const std::string& r : recent_)
        if (ImGui::Selectable(r.c_str())) {
          std::string path = r;  // openScene reorders recent_
          openScene(path);
          break;
        }
      ImGui::EndCombo();
    }
    ImGui::TextDisabled("or drop a .gltf/.glb on the window");
    drawSceneInfo(scene_);
  }
  if (ImGui::CollapsingHeader("Camera and lights")) {
    if (ImGui::Button("Reset camera (F)")) {
      camera_ = CameraController(sceneCamera_, glm::length(scene_.bounds.center() - sceneCamera_.position),
                                 scene_.bounds.diagonal());
      markStale(staleAfterCameraMove());
    }
    ImGui::TextDisabled("drag: orbit, right drag: pan, wheel: zoom, WASD/QE: fly");
    applyLightEdit(drawLightsPanel(scene_, lightOffsets_, lightScales_));
    ImGui::Checkbox("animate light", &animateLight_);
    ImGui::SameLine();
    ImGui::Checkbox("new seed every frame", &reseedEveryFrame_);
  }
  if (ImGui::CollapsingHeader("Many lights", ImGuiTreeNodeFlags_DefaultOpen)) {
    Settings next = settings_;
    if (drawManyLightPanel(next, vpls_.stats, clampEnergyRemoved_)) changeSettings(next);
    if (!offlineImage_.empty() && offlineImageMethod_ != Method::Reference) {
      ImGui::TextDisabled("exact render: clamp removed %.1f %% (all pixels)", 100.0 * offlineClampEnergy_);
      if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Measured by the exact VPL render over every pixel sample: the luminance its clamped VPL sum\n"
                          "lost against the unclamped one, of the VPL (indirect) light.");
    }
  }
  ImGui::PopItemWidth();
  ImGui::End();
}

void Editor::drawRightPanel() {
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  ImGui::SetNextWindowPos(ImVec2(display.x - kRightPanelWidth, 0));
  ImGui::SetNextWindowSize(ImVec2(kRightPanelWidth, display.y));
  ImGui::Begin("Analysis", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  ImGui::PushItemWidth(180.0f);

  if (ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) {
    int mode = static_cast<int>(view_);
    const char* names[] = {"preview", "reference", "split", "difference", "SSBC residual", "VPLs"};
    if (ImGui::Combo("view (1-6)", &mode, names, 6)) {
      view_ = static_cast<ViewMode>(mode);
      if (view_ == ViewMode::SsbcResidual) stale_.gather = true;  // the residual is read back on render
      displayDirty_ = true;
    }
    ImGui::Checkbox("fit preview to the view", &fitPreview_);
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("The image size follows the view area times the resolution scale; off: the offline\n"
                        "panel's image size, shown at integer zoom.");
    if (fitPreview_)
      ImGui::SliderFloat("resolution scale", &previewScale_, 0.1f, 1.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp);
    if (view_ == ViewMode::Split && ImGui::SliderFloat("divider", &divider_, 0.0f, 1.0f)) displayDirty_ = true;
    if (view_ == ViewMode::Difference) {
      if (ImGui::RadioButton("relative error", relativeDifference_)) relativeDifference_ = true, displayDirty_ = true;
      ImGui::SameLine();
      if (ImGui::RadioButton("signed", !relativeDifference_)) relativeDifference_ = false, displayDirty_ = true;
      ImGui::TextDisabled(relativeDifference_ ? "(I - R)^2 / (R^2 + 0.01), I preview, R offline"
                                              : "I - R: red too bright, blue too dark");
    }
    if (view_ == ViewMode::VplOverlay) ImGui::Checkbox("show rejected candidates", &showRejected_);
  }
  if (ImGui::CollapsingHeader("Offline pass", ImGuiTreeNodeFlags_DefaultOpen)) {
    Settings next = settings_;
    if (drawOfflineSettingsPanel(next)) {
      if (next.width != settings_.width || next.height != settings_.height) fitPreview_ = false;  // asked for a size
      changeSettings(next);
    }
    if (job_.running()) {
      double left = job_.secondsLeft();
      char overlay[32] = "";
      if (left >= 0.0) std::snprintf(overlay, sizeof(overlay), "%.0f s left", std::ceil(left));
      ImGui::ProgressBar(job_.progress(), ImVec2(180.0f, 0.0f), overlay[0] ? overlay : nullptr);
      ImGui::SameLine();
      if (ImGui::Button("Cancel")) job_.cancel();
      ImGui::Text("%s: %.1f s", toString(job_.method()), job_.seconds());
    } else {
      if (ImGui::Button("Render reference (O)")) startOffline(true);
      ImGui::SameLine();
      if (ImGui::Button("Render exact VPL")) startOffline(false);
      const OfflineTimeEstimate& estimate = offlineEstimates_[scene_.sourcePath];
      const Method exact = exactCounterpartOf(settings_);
      const double referenceSeconds =
          estimate.estimate(Method::Reference, offlineRenderSettings(settings_, Method::Reference), 0);
      const double exactSeconds = estimate.estimate(exact, offlineRenderSettings(settings_, exact), vpls_.vpls.size());
      auto seconds = [](double s) { return s < 0.0 ? std::string("?") : "~" + formatSeconds(s); };
      ImGui::TextDisabled("estimated: reference %s, %s %s", seconds(referenceSeconds).c_str(), toString(exact),
                          seconds(exactSeconds).c_str());
      if (ImGui::IsItemHovered())
        ImGui::SetTooltip("From the throughput of the last render of each kind on this scene (? before the first):\n"
                          "pixels x spp for the reference, x VPLs (x VSL samples) for an exact render.");
      if (!offlineImage_.empty())
        ImGui::Text("%s%s: %d spp in %.2f s%s", toString(offlineImageMethod_), job_.cancelled() ? " (cancelled)" : "",
                    job_.samplesPerPixel(), offlineSeconds_, offlineStale_ ? "  STALE" : "");
      if (!offlineImage_.empty() && job_.nonFiniteSamples() > 0)
        ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%llu NaN/Inf samples left out",
                           static_cast<unsigned long long>(job_.nonFiniteSamples()));
      if (!job_.error().empty()) ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", job_.error().c_str());
    }
    if (!offlineImage_.empty() && !previewLinear_.empty() && offlineImage_.width == previewLinear_.width &&
        offlineImage_.height == previewLinear_.height) {
      ImageMetrics m = compareImages(previewLinear_, offlineImage_);
      ImGui::Text("preview vs offline: relMSE %.4g, energy %.3f", m.relMse, m.energyRatioOverall);
    }
  }
  const int currentPoint = findChartPoint(chart_, settings_);
  int clicked = -1;
  if (chartWindowOpen_) {
    // A resizable window of its own, shown whether or not the panel's section is open; the chart fills it, leaving
    // room for the legend.
    ImGui::SetNextWindowSize(ImVec2(720.0f, 480.0f), ImGuiCond_FirstUseEver);
    if (ImGui::Begin("Speed vs accuracy chart", &chartWindowOpen_)) {
      ImVec2 room = ImGui::GetContentRegionAvail();
      clicked = drawSpeedAccuracyChart(chart_, currentPoint, room.x, room.y - 3.0f * ImGui::GetFrameHeightWithSpacing());
    }
    ImGui::End();
  }
  if (ImGui::CollapsingHeader("Speed vs accuracy", ImGuiTreeNodeFlags_DefaultOpen)) {
    if (chartWindowOpen_)
      ImGui::TextDisabled("The chart is in its own window.");
    else
      clicked = drawSpeedAccuracyChart(chart_, currentPoint, kRightPanelWidth - 24.0f, 240.0f);
    if (ImGui::SmallButton(chartWindowOpen_ ? "dock chart" : "enlarge chart")) chartWindowOpen_ = !chartWindowOpen_;
    ImGui::SameLine();
    if (ImGui::SmallButton("clear chart")) chart_.clear();
    // The last converged change: each pass's GPU time summed over the frames it took; a pass it did not re-run is
    // marked cached (its time when it last ran is lastPassMs_).
    const PreviewTimings& t = changeTimer_.lastPasses();
    std::vector<PassTiming> passes = {
        {"G-buffer", t.gbufferMs, lastPassMs_.gbufferMs},
        {"light shadows", t.directShadowMs, lastPassMs_.directShadowMs},
        {"direct", t.directMs, lastPassMs_.directMs},
        {"VPL shadows", t.vplShadowMs, lastPassMs_.vplShadowMs},
        {"gather", t.gatherMs, lastPassMs_.gatherMs},
        {"SSBC", t.ssbcMs, lastPassMs_.ssbcMs},
        {"tonemap", t.tonemapMs, lastPassMs_.tonemapMs},
        {"VPL generation (CPU)", changeTimer_.lastVplGenerationMs(), vpls_.stats.generationSeconds * 1e3}};
    if (changeTimer_.lastMs() >= 0.0)
      ImGui::TextDisabled("last change, %d frame%s; GPU ms per pass:", changeTimer_.lastFrames(),
                          changeTimer_.lastFrames() == 1 ? "" : "s");
    drawPassTimings(passes);
  }
  if (clicked >= 0 && clicked < static_cast<int>(chart_.size()))
    changeSettings(chart_[static_cast<std::size_t>(clicked)].settings);
  if (ImGui::CollapsingHeader("Teaching presets")) {
    ImGui::TextDisabled("The explanation is shown above the view.");
    for (const TeachingPreset& p : teachingPresets())
      if (ImGui::Button(p.name.c_str(), ImVec2(kRightPanelWidth - 30.0f, 0.0f))) applyPreset(p);
  }
  if (ImGui::CollapsingHeader("Files")) {
    ImGui::InputText("settings", &settingsPath_);
    if (ImGui::Button("Save settings")) {
      try {
        saveSettingsFile(settingsPath_, settings_);
        ioMessage_ = "saved " + settingsPath_;
      } catch (const std::exception& e) {
        ioMessage_ = e.what();
      }
    }
    ImGui::SameLine();
    if (ImGui::Button("Load settings")) {
      try {
        Settings next = settings_;
        loadSettingsFile(settingsPath_, next);
        if (next.width != settings_.width || next.height != settings_.height) fitPreview_ = false;
        changeSettings(next);
        ioMessage_ = "loaded " + settingsPath_;
      } catch (const std::exception& e) {
        ioMessage_ = e.what();
      }
    }
    if (ImGui::Button("Save lights")) {
      // Next to the scene file; opening the scene again (editor or CLI) applies it.
      try {
        saveLightsFile(lightsSidecarPath(scene_.sourcePath), scene_);
        ioMessage_ = "saved " + lightsSidecarPath(scene_.sourcePath);
      } catch (const std::exception& e) {
        ioMessage_ = e.what();
      }
    }
    ImGui::InputText("image", &exportPath_);
    auto exportImage = [&](const Image& image) {
      try {
        if (image.empty()) throw std::runtime_error("nothing to export yet");
        writeImage(exportPath_, image, settings_.exposure);
        ioMessage_ = "wrote " + exportPath_;
      } catch (const std::exception& e) {
        ioMessage_ = e.what();
      }
    };
    if (ImGui::Button("Export preview")) exportImage(previewLinear_);
    ImGui::SameLine();
    if (ImGui::Button("Export offline")) exportImage(offlineImage_);
    ImGui::TextDisabled(".png (tonemapped), .exr or .pfm (linear)");
    if (!ioMessage_.empty()) ImGui::TextWrapped("%s", ioMessage_.c_str());
  }
  if (ImGui::CollapsingHeader("Help (H)") || showHelp_) {
    ImGui::TextWrapped(
        "Mouse: left drag orbit, right/middle drag pan, wheel zoom; in split view drag the divider.\n"
        "Keys: WASD fly, Q/E down/up, F reset camera, 1-6 views, O render reference, Esc cancel offline, "
        "H help.\nChanging b re-gathers only; moving the camera never regenerates VPLs; moving a light does.");
  }
  ImGui::PopItemWidth();
  ImGui::End();
}

void Editor::drawUi() {
  drawView();
  drawLeftPanel();
  drawRightPanel();
}

// --- script -------------------------------------------------------------------------------------------------------

void Editor::scriptFail(const ScriptCommand& c, const std::string& message) {
  throw ScriptError(options_.scriptPath + ":" + std::to_string(c.line) + ": " + c.verb + ": " + message);
}

void Editor::scriptStep() {
  if (framesPending_ > 0) {
    --framesPending_;
    return;
  }
  if (!pendingScreenshot_.empty()) return;  // the next command waits until the screenshot was taken
  if (timingFrames_ > 0) {
    if (timingLight_ >= 0) {
      // A light drag: the light moves 0.2 % of the scene diagonal every frame, back and forth over 40 frames.
      const float step = 0.002f * scene_.bounds.diagonal() * ((timingTotal_ - timingFrames_) / 20 % 2 ? -1.0f : 1.0f);
      editLight(static_cast<std::size_t>(timingLight_), glm::vec3(step, 0.0f, 0.0f), 1.0f);
    } else {
      // Each timed frame moves the camera a little so that the preview re-renders, as it does while a user orbits.
      camera_.orbit(0.01f, 0.0f);
      markStale(staleAfterCameraMove());
    }
    return;
  }
  if (waitingOffline_) {
    if (job_.running()) return;
    waitingOffline_ = false;
  }
  if (finalScreenshotQueued_) {
    quit_ = true;
    return;
  }
  while (scriptIndex_ < script_.size()) {
    const ScriptCommand& c = script_[scriptIndex_++];
    try {
      execute(c);
    } catch (const ScriptError&) {
      throw;
    } catch (const std::exception& e) {
      scriptFail(c, e.what());
    }
    if (framesPending_ > 0 || waitingOffline_ || timingFrames_ > 0 || !pendingScreenshot_.empty()) return;
  }
  // Script done: the final screenshot after two more frames, then exit.
  if (!options_.screenshotPath.empty()) {
    framesPending_ = 2;
    script_.push_back({0, "screenshot", {options_.screenshotPath}});
    options_.screenshotPath.clear();
    return;
  }
  finalScreenshotQueued_ = true;
}

void Editor::execute(const ScriptCommand& c) {
  const std::string& src = options_.scriptPath;
  auto num = [&](std::size_t i) { return static_cast<float>(scriptNumber(c, i, src)); };
  if (c.verb == "set") {
    Settings next = settings_;
    setSettingFromText(next, c.args[0], c.args[1]);
    if (next.width != settings_.width || next.height != settings_.height || c.args[0] == "width" ||
        c.args[0] == "height")
      fitPreview_ = false;  // an explicit image size
    changeSettings(next);
  } else if (c.verb == "orbit") {
    camera_.orbit(glm::radians(num(0)), glm::radians(num(1)));
    markStale(staleAfterCameraMove());
  } else if (c.verb == "pan") {
    camera_.pan(num(0), num(1));
    markStale(staleAfterCameraMove());
  } else if (c.verb == "zoom") {
    camera_.zoom(num(0));
    markStale(staleAfterCameraMove());
  } else if (c.verb == "reset-camera") {
    camera_ = CameraController(sceneCamera_, glm::length(scene_.bounds.center() - sceneCamera_.position),
                               scene_.bounds.diagonal());
    markStale(staleAfterCameraMove());
  } else if (c.verb == "light") {
    auto index = static_cast<std::size_t>(num(0));
    if (c.args[1] == "move")
      editLight(index, glm::vec3(num(2), num(3), num(4)), 1.0f);
    else
      editLight(index, glm::vec3(0.0f), num(2));
  } else if (c.verb == "view") {
    bool found = false;
    for (ViewMode m : kAllViewModes)
      if (c.args[0] == toString(m)) view_ = m, found = true;
    if (!found) scriptFail(c, "unknown view '" + c.args[0] + "'");
    if (view_ == ViewMode::SsbcResidual) stale_.gather = true;
    displayDirty_ = true;
  } else if (c.verb == "preset") {
    const TeachingPreset* preset = findPreset(c.args[0]);
    if (!preset) scriptFail(c, unknownPresetMessage(c.args[0]));
    if (!applyPreset(*preset)) scriptFail(c, sceneError_);
    std::printf("%s\n", presetDescription(*preset).c_str());
    std::fflush(stdout);
  } else if (c.verb == "preview-scale") {
    fitPreview_ = true;
    previewScale_ = std::clamp(num(0), 0.05f, 1.0f);
  } else if (c.verb == "change-cost") {
    std::printf("change-cost size=%dx%d ms=%.1f frames=%d pending=%d\n", settings_.width, settings_.height,
                changeTimer_.lastMs(), changeTimer_.lastFrames(), changeTimer_.pending());
    std::fflush(stdout);
  } else if (c.verb == "preset-state") {
    std::printf("preset-state %s\n", presetState().c_str());
    std::fflush(stdout);
  } else if (c.verb == "frames") {
    framesPending_ = std::max(0, static_cast<int>(num(0)));
  } else if (c.verb == "screenshot") {
    pendingScreenshot_ = c.args[0];
  } else if (c.verb == "save-view") {
    finishWork();
    if (previewLinear_.empty()) scriptFail(c, "no preview image");
    writeImage(c.args[0], previewLinear_, settings_.exposure);
    std::printf("save-view %s %dx%d\n", c.args[0].c_str(), previewLinear_.width, previewLinear_.height);
  } else if (c.verb == "offline") {
    finishWork();  // the offline pass must use the VPLs of the current settings
    startOffline(c.args[0] == "reference");
  } else if (c.verb == "wait-offline") {
    waitingOffline_ = true;
  } else if (c.verb == "load-settings") {
    Settings next = settings_;
    loadSettingsFile(c.args[0], next);
    if (next.width != settings_.width || next.height != settings_.height) fitPreview_ = false;
    changeSettings(next);
  } else if (c.verb == "save-settings") {
    saveSettingsFile(c.args[0], settings_);
  } else if (c.verb == "mark") {
    finishWork();  // what is stale now belongs before the mark
    mark_ = counters();
  } else if (c.verb == "expect-no-vpl-regeneration" || c.verb == "expect-no-shadow-map-render" ||
             c.verb == "expect-vpl-regeneration") {
    finishWork();
    WorkCounters n = counters();
    int generations = n.vplGenerations - mark_.vplGenerations;
    int shadowMaps = n.vplShadowMaps - mark_.vplShadowMaps;
    if (c.verb == "expect-no-vpl-regeneration" && generations != 0)
      scriptFail(c, std::to_string(generations) + " VPL generation(s) since the mark");
    if (c.verb == "expect-no-shadow-map-render" && shadowMaps != 0)
      scriptFail(c, std::to_string(shadowMaps) + " VPL shadow-map render(s) since the mark");
    if (c.verb == "expect-vpl-regeneration" && generations == 0) scriptFail(c, "no VPL generation since the mark");
  } else if (c.verb == "counters") {
    finishWork();
    WorkCounters n = counters();
    std::printf("counters vplGenerations=%d vplShadowMaps=%d gathers=%d\n", n.vplGenerations, n.vplShadowMaps,
                n.gathers);
    std::fflush(stdout);
  } else if (c.verb == "time-frames") {
    timingTotal_ = timingFrames_ = std::max(1, static_cast<int>(num(0)));
    timingFrameSum_ = timingUiSum_ = timingPreviewSum_ = 0.0;
    timingFrameMs_.clear();
    timingUpdates_ = updatesFinished_;
    timingLight_ = -1;
    if (c.args.size() >= 3 && c.args[1] == "light") {
      timingLight_ = static_cast<int>(num(2));
      if (timingLight_ < 0 || static_cast<std::size_t>(timingLight_) >= editableLights(scene_).size())
        scriptFail(c, "no light " + c.args[2]);
    } else if (c.args.size() != 1) {
      scriptFail(c, "usage: time-frames N [light I]");
    }
  }
}

}  // namespace

int runEditor(const EditorOptions& options) {
  Editor editor(options);
  try {
    return editor.run();
  } catch (const ScriptError& e) {
    std::fprintf(stderr, "vplab edit: %s\n", e.what());
    return 1;
  }
}

}  // namespace vplab::ui
