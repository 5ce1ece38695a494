#include "ui/editor.h"

#include "renderer/core/text.h"
#include "renderer/core/atomic_file.h"
#include "renderer/gl/context.h"
#include "renderer/image/image_io.h"
#include "ui/editor_panels.h"
#include "ui/editor_state.h"
#include "ui/script.h"
#include "ui/view_image.h"

// glad first: it must define the GL prototypes before GLFW looks for any.
#include <glad/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <stdexcept>

namespace vplab::ui {

namespace {

// Window clear colour, which is also the panels' background (see Editor's ImGui style set-up).
constexpr float kBackground[3] = {0.07f, 0.07f, 0.075f};
/// The preview's work is split across frames of about this much, plus the slice that crosses it (at most about
/// PassSlices::kSliceMs, 20 ms): with the UI's 5-15 ms a frame takes about 75 ms, which leaves half of a 150 ms frame for
/// what a slice cannot split (a shader's first compile, another process taking the shared cores).
constexpr double kPreviewFrameBudgetMs = 40.0;

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
  void upload(const ViewImage& image) {
    if (image.rgb.empty()) return;
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
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, image.width, image.height, 0, GL_RGB, GL_UNSIGNED_BYTE, image.rgb.data());
    width_ = image.width;
    height_ = image.height;
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

 private:
  GLuint id_ = 0, framebuffer_ = 0;
  int width_ = 0, height_ = 0;
};

/// The window's share of a script: the verbs that span frames (frames, screenshot, wait-offline, time-frames).
struct ScriptRun {
  std::vector<ScriptCommand> commands;
  std::size_t next = 0;
  int framesPending = 0;
  bool waitingOffline = false;
  std::string pendingScreenshot;
  bool finalScreenshotQueued = false;
  // time-frames: frames left and in all, each frame's time (ms), what is dragged (-1: the camera orbits), the updates
  // finished before, and the sums of the frame, UI and preview times.
  int timingFrames = 0, timingTotal = 0;
  std::vector<double> frameMs;
  enum class Drag { Camera, Light, Medium } drag = Drag::Camera;
  int dragIndex = -1, updatesBefore = 0;
  double frameSum = 0.0, uiSum = 0.0, previewSum = 0.0;
};

class Editor {
 public:
  explicit Editor(const EditorOptions& options);
  ~Editor();
  int run();

 private:
  void frame();
  void handleInput();
  void takeScreenshot(const std::string& path);
  void scriptStep();
  /// The window's verbs; the others go to runStateCommand.
  void execute(const ScriptCommand& c);
  /// One frame of a time-frames drag.
  void dragStep();
  void recordFrameTime(double frameMs, double uiMs, double previewMs, int width, int height);

  EditorOptions options_;
  GLFWwindow* window_ = nullptr;
  std::unique_ptr<EditorState> state_;
  PanelState panels_;
  DisplayTexture texture_;
  ViewImage shown_;
  ViewPlacement placed_;
  bool draggingDivider_ = false;
  double frameMs_ = 0.0;  ///< the last frame's time
  ScriptRun script_;
  bool quit_ = false;
};

Editor::Editor(const EditorOptions& options) : options_(options) {
  if (!options.scriptPath.empty()) script_.commands = loadScript(options.scriptPath);  // typos fail before the window
  // A screenshot without a script is a script of its own: render, capture, exit.
  if (options.scriptPath.empty() && !options.screenshotPath.empty()) script_.commands.push_back({0, "frames", {"1"}});
  // The scene first: a bad file fails before a window is opened (the state needs GL only for its first update).
  state_ = std::make_unique<EditorState>(options.scenePath, options.settings, options.fitPreview, options.previewScale);

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
  glfwSwapInterval(script_.commands.empty() ? 1 : 0);
  glfwSetWindowUserPointer(window_, this);
  glfwSetDropCallback(window_, [](GLFWwindow* w, int count, const char** paths) {
    auto* editor = static_cast<Editor*>(glfwGetWindowUserPointer(w));
    if (count > 0) openDroppedFile(*editor->state_, editor->panels_, paths[0]);
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

  state_->setDisplaySize(static_cast<float>(options.windowWidth), static_cast<float>(options.windowHeight));

  if (std::ifstream in(recentFilesPath()); in)
    for (std::string line; std::getline(in, line);)
      if (!line.empty()) panels_.recent.push_back(line);
  panels_.pathInput = options.scenePath;
  if (script_.commands.empty()) {
    auto& recent = panels_.recent;
    recent.erase(std::remove(recent.begin(), recent.end(), options.scenePath), recent.end());
    recent.insert(recent.begin(), options.scenePath);
  }
  // UI windows are hidden on their first frame (ImGui lays a window out before it shows it): scripts start after two.
  script_.framesPending = script_.commands.empty() ? 0 : 2;
}

Editor::~Editor() {
  state_.reset();  // its preview's GL objects go while the context is current
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  if (window_) glfwDestroyWindow(window_);
  glfwTerminate();
  if (script_.commands.empty() && !recentFilesPath().empty()) {
    // Best effort at exit: a list that cannot be saved is not worth an error, but it is never left cut.
    std::string text;
    for (std::size_t i = 0; i < panels_.recent.size() && i < 10; ++i) text += panels_.recent[i] + "\n";
    try {
      writeFileAtomically(recentFilesPath(), text);
    } catch (const FileWriteError& e) {
      std::fprintf(stderr, "vplab edit: %s\n", printableMessage(e.what()).c_str());
    }
  }
}

// --- frame --------------------------------------------------------------------------------------------------------

void Editor::handleInput() {
  ImGuiIO& io = ImGui::GetIO();
  EditorState& state = *state_;
  CameraController& camera = state.camera();
  bool cameraMoved = false;
  if (!io.WantCaptureMouse) {
    const ImVec2 delta = io.MouseDelta;
    const float radiansPerPixel = 0.005f;
    ViewOptions& view = state.viewForEditing();
    const float divX = placed_.x + view.divider * placed_.w;
    if (view.view == ViewMode::Split && io.MouseClicked[0] && std::abs(io.MousePos.x - divX) < 6.0f)
      draggingDivider_ = true;
    if (!io.MouseDown[0]) draggingDivider_ = false;
    if (draggingDivider_) {
      view.divider = std::clamp((io.MousePos.x - placed_.x) / std::max(placed_.w, 1.0f), 0.0f, 1.0f);
      state.viewChanged();
    } else if (io.MouseDown[0] && (delta.x != 0.0f || delta.y != 0.0f)) {
      camera.orbit(-delta.x * radiansPerPixel, -delta.y * radiansPerPixel);
      cameraMoved = true;
    } else if ((io.MouseDown[1] || io.MouseDown[2]) && (delta.x != 0.0f || delta.y != 0.0f)) {
      camera.pan(-delta.x * 0.002f, delta.y * 0.002f);
      cameraMoved = true;
    }
    if (io.MouseWheel != 0.0f) {
      camera.zoom(io.MouseWheel);
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
      camera.fly(fly.x, fly.y, fly.z);
      cameraMoved = true;
    }
    if (ImGui::IsKeyPressed(GLFW_KEY_F)) state.resetCamera();
    for (int i = 0; i < 7; ++i)
      if (ImGui::IsKeyPressed(GLFW_KEY_1 + i)) state.setView(kAllViewModes[i]);
    if (ImGui::IsKeyPressed(GLFW_KEY_O) && !state.job().running()) state.startOffline(OfflineRequest::Reference);
    if (ImGui::IsKeyPressed(GLFW_KEY_ESCAPE)) state.job().cancel();
    if (ImGui::IsKeyPressed(GLFW_KEY_H) || ImGui::IsKeyPressed(GLFW_KEY_F1)) panels_.showHelp = !panels_.showHelp;
  }
  if (cameraMoved) state.cameraMoved();
}

void Editor::frame() {
  EditorState& state = *state_;
  const double start = steadySeconds();
  if (state.busy() || !script_.commands.empty())
    glfwPollEvents();
  else
    glfwWaitEventsTimeout(0.1);  // idle: do not spin two shared cores for an unchanged picture

  if (!script_.commands.empty()) scriptStep();
  if (quit_) return;
  state.animate();
  state.pollOffline();

  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  const double uiStart = steadySeconds();
  ImGui::NewFrame();
  handleInput();
  const double uiPause = steadySeconds();
  state.updateWork(kPreviewFrameBudgetMs);
  if (state.takeDisplayDirty()) {
    shown_ = composeView(state);
    texture_.upload(shown_);
  }
  glFinish();
  const double previewEnd = steadySeconds();
  drawView(state, shown_, frameMs_, placed_);
  drawLeftPanel(state, panels_);
  drawRightPanel(state, panels_);
  ImGui::Render();
  int width, height;
  glfwGetFramebufferSize(window_, &width, &height);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, width, height);
  glClearColor(kBackground[0], kBackground[1], kBackground[2], 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  glFinish();
  // Showing the image is part of the preview's time, like its readback and upload; the UI draws over it.
  const double viewStart = steadySeconds();
  if (!shown_.rgb.empty() && shown_.emptyState.empty()) {
    // The placement is in ImGui's window coordinates; the framebuffer may have more pixels (HiDPI).
    const ImVec2 fb = ImGui::GetIO().DisplayFramebufferScale;
    texture_.blitTo(placed_.x * fb.x, placed_.y * fb.y, placed_.w * fb.x, placed_.h * fb.y, height,
                    placed_.scale != std::floor(placed_.scale));
  }
  glFinish();
  const double viewEnd = steadySeconds();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  glFinish();
  const double uiEnd = steadySeconds();
  // A screenshot shows a finished image; an animated light never lets the image finish, so it takes the frame as is.
  if (!script_.pendingScreenshot.empty() &&
      ((!state.previewUpdating() && !state.previewStale()) || state.animateLight || !state.previewError().empty())) {
    takeScreenshot(script_.pendingScreenshot);
    script_.pendingScreenshot.clear();
  }
  glfwSwapBuffers(window_);
  frameMs_ = (steadySeconds() - start) * 1e3;
  if (script_.timingFrames > 0)
    recordFrameTime(frameMs_, ((uiPause - uiStart) + (viewStart - previewEnd) + (uiEnd - viewEnd)) * 1e3,
                    ((previewEnd - uiPause) + (viewEnd - viewStart)) * 1e3, width, height);
}

void Editor::recordFrameTime(double frameMs, double uiMs, double previewMs, int width, int height) {
  ScriptRun& t = script_;
  t.frameMs.push_back(frameMs);
  t.frameSum += frameMs;
  t.uiSum += uiMs;
  t.previewSum += previewMs;
  if (--t.timingFrames > 0) return;
  const double n = t.timingTotal;
  std::vector<double> sorted = t.frameMs;
  std::sort(sorted.begin(), sorted.end());
  auto quantile = [&](double q) {
    return sorted[std::min(sorted.size() - 1, static_cast<std::size_t>(q * sorted.size()))];
  };
  const char* what = t.drag == ScriptRun::Drag::Light    ? "light-drag"
                     : t.drag == ScriptRun::Drag::Medium ? "medium-drag"
                                                         : "orbit";
  const Settings& s = state_->settings();
  std::printf(
      "frame-time frames=%d size=%dx%d window=%dx%d frame_ms=%.2f p50_ms=%.2f p95_ms=%.2f max_ms=%.2f "
      "preview_ms=%.2f ui_ms=%.2f ui_share=%.1f%% updates=%d last_update_ms=%.1f while=%s\n",
      t.timingTotal, s.width, s.height, width, height, t.frameSum / n, quantile(0.5), quantile(0.95), sorted.back(),
      t.previewSum / n, t.uiSum / n, 100.0 * t.uiSum / t.frameSum, state_->updatesFinished() - t.updatesBefore,
      state_->lastUpdateMs(), what);
  std::fflush(stdout);
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
              static_cast<int>(placed_.x), static_cast<int>(placed_.y), static_cast<int>(placed_.w),
              static_cast<int>(placed_.h), placed_.scale);
  std::fflush(stdout);
}

int Editor::run() {
  while (!quit_ && !glfwWindowShouldClose(window_)) frame();
  return 0;
}

// --- script -------------------------------------------------------------------------------------------------------

void Editor::dragStep() {
  EditorState& state = *state_;
  // Back and forth over 40 frames, so the drag stays near where it started.
  const float sign = (script_.timingTotal - script_.timingFrames) / 20 % 2 ? -1.0f : 1.0f;
  if (script_.drag == ScriptRun::Drag::Light) {
    // The light moves 0.2 % of the scene diagonal every frame.
    state.editLight(static_cast<std::size_t>(script_.dragIndex),
                    glm::vec3(0.002f * state.scene().bounds.diagonal() * sign, 0.0f, 0.0f), 1.0f);
  } else if (script_.drag == ScriptRun::Drag::Medium) {
    // sigma_s changes by 2 % every frame, as a slider dragged slowly.
    std::vector<Medium> media = state.media();
    media[static_cast<std::size_t>(script_.dragIndex)].sigmaS *= sign > 0.0f ? 1.02f : 1.0f / 1.02f;
    state.editMedia(media);
  } else {
    // Each timed frame moves the camera a little so that the preview re-renders, as it does while a user orbits.
    state.camera().orbit(0.01f, 0.0f);
    state.cameraMoved();
  }
}

void Editor::scriptStep() {
  ScriptRun& s = script_;
  if (s.framesPending > 0) {
    --s.framesPending;
    return;
  }
  if (!s.pendingScreenshot.empty()) return;  // the next command waits until the screenshot was taken
  if (s.timingFrames > 0) {
    dragStep();
    return;
  }
  if (s.waitingOffline) {
    if (state_->job().running()) return;
    s.waitingOffline = false;
  }
  if (s.finalScreenshotQueued) {
    quit_ = true;
    return;
  }
  while (s.next < s.commands.size()) {
    const ScriptCommand& c = s.commands[s.next++];
    if (!runStateCommand(*state_, c, options_.scriptPath)) execute(c);
    if (s.framesPending > 0 || s.waitingOffline || s.timingFrames > 0 || !s.pendingScreenshot.empty()) return;
  }
  // Script done: the final screenshot after two more frames, then exit.
  if (!options_.screenshotPath.empty()) {
    s.framesPending = 2;
    s.commands.push_back({0, "screenshot", {options_.screenshotPath}});
    options_.screenshotPath.clear();
    return;
  }
  s.finalScreenshotQueued = true;
}

void Editor::execute(const ScriptCommand& c) {
  const std::string& src = options_.scriptPath;
  ScriptRun& s = script_;
  auto fail = [&](const std::string& message) {
    throw ScriptError(src + ":" + std::to_string(c.line) + ": " + c.verb + ": " + message);
  };
  if (c.verb == "frames") {
    s.framesPending = std::max(0, static_cast<int>(scriptNumber(c, 0, src)));
  } else if (c.verb == "screenshot") {
    s.pendingScreenshot = c.args[0];
  } else if (c.verb == "wait-offline") {
    s.waitingOffline = true;
  } else if (c.verb == "time-frames") {
    s.timingTotal = s.timingFrames = std::max(1, static_cast<int>(scriptNumber(c, 0, src)));
    s.frameSum = s.uiSum = s.previewSum = 0.0;
    s.frameMs.clear();
    s.updatesBefore = state_->updatesFinished();
    s.drag = ScriptRun::Drag::Camera;
    if (c.args.size() == 3 && (c.args[1] == "light" || c.args[1] == "medium")) {
      const bool light = c.args[1] == "light";
      s.drag = light ? ScriptRun::Drag::Light : ScriptRun::Drag::Medium;
      s.dragIndex = static_cast<int>(scriptNumber(c, 2, src));
      const std::size_t count = light ? editableLights(state_->scene()).size() : state_->media().size();
      if (s.dragIndex < 0 || static_cast<std::size_t>(s.dragIndex) >= count) fail("no " + c.args[1] + " " + printable(c.args[2]));
    } else if (c.args.size() != 1) {
      fail("usage: time-frames N [light|medium I]");
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
