#pragma once
// The editor's state and the scheduling of its work, without a window: the scene and its edits (lights, media), the
// Settings, the VplSet, the preview's work spread across frames, the offline job, the chart's data, the view options
// and the active teaching preset. Panels (ui/side_panels.cpp, ui/media_panel.cpp) only draw it and call its member
// functions; the script verbs (ui/script.cpp) call the same functions; tests drive it with a headless GL context.
// Every edit goes through one function that asks renderer/invalidation.h what it made stale, and updateWork() re-runs
// exactly that, as Dear ImGui's examples keep the application's data apart from the widgets that edit it.
//
// The preview is made by the first updateWork(), which needs a current GL 4.5 context from then on (the window's, or
// HeadlessGlContext); the edits and their invalidation need none.

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "renderer/gl/preview_renderer.h"
#include "renderer/image/image.h"
#include "renderer/invalidation.h"
#include "renderer/offline/lightcuts_renderer.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/offline/representative_lights.h"
#include "renderer/scene/scene.h"
#include "renderer/settings.h"
#include "renderer/vpl/vpl.h"
#include "ui/camera_controller.h"
#include "ui/change_timer.h"
#include "ui/chart.h"
#include "ui/coarse_preview.h"
#include "ui/offline_job.h"
#include "ui/panels.h"
#include "ui/presets.h"
#include "ui/view_mode.h"

namespace vplab::ui {

/// How often the expensive stages ran since the state was made (scripts and tests check invalidation with these).
struct WorkCounters {
  int vplGenerations = 0;
  int vplShadowMaps = 0;
  int gathers = 0;
};

/// What the view shows and how; the window's panels edit these directly and then call EditorState::viewChanged().
struct ViewOptions {
  ViewMode view = ViewMode::Preview;
  float divider = 0.5f;            ///< split view: share of the image left of the divider
  bool relativeDifference = true;  ///< difference view: relative error (else signed)
  bool showRejected = false;       ///< VPL view: also the candidates rejection dropped
  bool showMediumBoxes = true;     ///< every view: the outlines of the medium boxes (a density grid's bounds)
};

/// Which offline render the editor's offline pass starts.
enum class OfflineRequest {
  Reference,  ///< the path-traced reference
  Exact,      ///< the exact CPU counterpart of the preview (exactCounterpartOf)
  Chosen,     ///< EditorState::offlineMethod(), any row of the render-method table
};

class EditorState {
 public:
  /// Loads the scene (SceneError when it cannot be loaded) and validates the settings (std::invalid_argument).
  EditorState(const std::string& scenePath, const Settings& settings, bool fitPreview, float previewScale);
  ~EditorState();
  EditorState(const EditorState&) = delete;
  EditorState& operator=(const EditorState&) = delete;

  // --- scene, lights and media ---------------------------------------------------------------------------------
  /// Opens a scene; a file that fails leaves the current scene and sets sceneError().
  bool openScene(const std::string& path);
  const Scene& scene() const { return scene_; }
  const std::string& sceneError() const { return sceneError_; }
  /// Moves light `index` (editableLights order) by `offset` and scales it by `scale`. Throws std::out_of_range.
  void editLight(std::size_t index, const glm::vec3& offset, float scale);
  /// The lights panel edits the scene in place and reports what changed: this rebuilds what that made stale.
  void applyLightEdit(LightEdit edit);
  /// The lights panel's per-light offsets and scales (what has been applied since the scene was opened).
  std::vector<glm::vec3>& lightOffsets() { return lightOffsets_; }
  std::vector<float>& lightScales() { return lightScales_; }
  Scene& sceneForLightsPanel() { return scene_; }
  /// Replaces the scene's media (a box added, removed, moved, resized; coefficients or g changed). Media the loader
  /// would refuse (mediaProblem) are refused with its message, which mediaError() then holds, and the scene keeps its
  /// media. Returns whether they were applied.
  bool editMedia(const std::vector<Medium>& next);
  /// The media as edited: what the panels show and edit. The scene takes them when the next preview update starts
  /// (an update under way keeps the media it started with, as it keeps its settings and camera).
  const std::vector<Medium>& media() const { return media_; }
  const std::string& mediaError() const { return mediaError_; }
  /// Writes the scene's lights and media to the sidecar next to the scene file; returns the path.
  std::string saveSidecar();

  // --- camera --------------------------------------------------------------------------------------------------
  CameraController& camera() { return camera_; }
  const CameraController& camera() const { return camera_; }
  /// After orbit, pan, zoom or fly through camera(): the G-buffer and what follows are stale.
  void cameraMoved();
  void resetCamera();

  // --- settings --------------------------------------------------------------------------------------------------
  const Settings& settings() const { return settings_; }
  /// Takes `next` when it is valid and marks what the change made stale. An explicit image size (one that differs
  /// from the current one) turns fitting off.
  void changeSettings(const Settings& next);
  /// The settings file's or a panel's settings: as changeSettings, and a size they name is kept (fitting off).
  void requestSettings(const Settings& next);
  bool fitPreview() const { return fitPreview_; }
  void setFitPreview(bool fit) { fitPreview_ = fit; }
  float previewScale() const { return previewScale_; }
  void setPreviewScale(float scale);
  /// The window's display size in pixels: the fitted preview's size follows the view area in it.
  void setDisplaySize(float width, float height);
  /// previewScale times the space the view has for the image (window pixels), with or without the preset box.
  glm::ivec2 fittedPreviewSize(bool presetBox) const;
  /// While fitting: takes the fitted size when it changed (a resized window, a preset box shown or closed).
  void fitPreviewToView();

  // --- view -------------------------------------------------------------------------------------------------------
  const ViewOptions& view() const { return view_; }
  ViewOptions& viewForEditing() { return view_; }
  /// After view options changed: the image is composed again; the SSBC residual is read back on the next render.
  void viewChanged();
  void setView(ViewMode mode);

  // --- work ------------------------------------------------------------------------------------------------------
  /// One frame's share of the stale work: VPLs, clamp figures, the preview's passes within about budgetMs.
  void updateWork(double budgetMs);
  /// updateWork() until the preview is complete (script verbs that read the image or the counters; tests).
  void finishWork();
  /// Something is being brought up to date (the preview, the offline job, an animation).
  bool busy() const;
  bool previewUpdating() const { return previewUpdating_; }
  bool previewStale() const { return stale_.anyPreview(); }
  float previewProgress() const { return previewProgress_; }
  const std::string& previewError() const { return previewError_; }
  const Image& previewImage() const { return previewLinear_; }
  const Image& residualImage() const { return residual_; }
  const VplSet& vpls() const { return vpls_; }
  /// The lights the preview gathers: the VPLs, or their representatives for the view when there are more than
  /// Settings::previewRepresentatives (representative_lights.h), as of the last update that started.
  const VplSet& previewVpls() const { return previewReduced_ ? previewSet_ : vpls_; }
  /// The last choice of representatives (what it cost, how many moved); empty before the first update.
  RepresentativeStats representativeStats() const {
    return representatives_ ? representatives_->stats() : RepresentativeStats{};
  }
  /// Share of the indirect energy the clamp removes at sample points; < 0 until measured.
  double clampEnergyRemoved() const { return clampEnergyRemoved_; }
  const std::vector<bool>& vplsSeen() const { return vplSeen_; }
  WorkCounters counters() const;
  const ChangeTimer& changeTimer() const { return changeTimer_; }
  /// The most recent non-zero time of each preview pass: the cost of a full frame.
  const PreviewTimings& lastPassMs() const { return lastPassMs_; }
  int updatesFinished() const { return updatesFinished_; }
  double lastUpdateMs() const { return lastUpdateMs_; }
  /// True once after the displayed image (or what composes it) changed.
  bool takeDisplayDirty();

  // --- offline pass ------------------------------------------------------------------------------------------------
  /// The method the offline panel's third button renders (vpl-abc, vrl, vbl in a scene with media).
  Method offlineMethod() const { return chosenOfflineMethod_; }
  void setOfflineMethod(Method method) { chosenOfflineMethod_ = method; }
  void startOffline(OfflineRequest request);
  /// Takes the running job's image and its end.
  void pollOffline();
  OfflineJob& job() { return job_; }
  const OfflineJob& job() const { return job_; }
  const Image& offlineImage() const { return offlineImage_; }
  Method offlineImageMethod() const { return offlineImageMethod_; }
  bool offlineStale() const { return offlineStale_; }
  double offlineSeconds() const { return offlineSeconds_; }
  double offlineClampEnergy() const { return offlineClampEnergy_; }
  /// The last lightcuts render's per-pixel cut size (light-tree nodes) and what it says; empty before one.
  const Image& cutSize() const { return cutSize_; }
  const CutSizeSummary& cutSummary() const { return cutSummary_; }
  /// Seconds an offline render of `method` with the current settings would take (< 0: unknown).
  double offlineEstimate(Method method) const;

  // --- chart -------------------------------------------------------------------------------------------------------
  const std::vector<ChartPoint>& chart() const { return chart_; }
  void clearChart() { chart_.clear(); }

  // --- presets and animation ---------------------------------------------------------------------------------------
  /// Applies a teaching preset from scratch: its scene reloaded (lights as in the file, the scene camera), its
  /// complete settings, its view and view options, and what it starts.
  bool applyPreset(const TeachingPreset& preset);
  const TeachingPreset* activePreset() const { return activePreset_; }
  void closePreset() { activePreset_ = nullptr; }
  /// The preset's settings as applied here: this machine's thread count, the fitted preview's size.
  Settings presetSettingsHere(const TeachingPreset& preset) const;
  /// Everything applyPreset sets, as one line (the preset-state script verb).
  std::string presetState() const;
  /// A change shows a coarse image of its new state first (CoarsePreview) when the last update that redid the same
  /// stages (else the last update) took longer than this, without its own coarse image (ms): the first image of an
  /// orbit within about 100 ms where the full one takes several frames. Infinity: never.
  double coarseFirstAfterMs = 100.0;
  bool animateLight = false;      ///< moves the first light on a small circle every frame
  bool reseedEveryFrame = false;  ///< a new seed every frame (the flicker demonstration)
  /// One frame of the light animation, when it is on.
  void animate();

  // --- script marks -------------------------------------------------------------------------------------------------
  /// Remembers the work counters (after finishing what is stale now).
  void mark();
  /// Counters since mark(), after finishing what is stale now.
  WorkCounters sinceMark();

 private:
  void rebuildAcceleration();
  void markStale(const Staleness& s);
  /// Tells the full-size and the coarse preview renderer alike (one of PreviewRenderer's invalidate functions).
  void invalidatePreviews(void (PreviewRenderer::*what)());
  void regenerateVpls();
  /// Chooses the preview's lights for the update that starts (the representatives stage).
  void chooseRepresentatives();
  void measureClampEnergy();
  void measureVplsSeen();
  void addChartPoint();
  /// The scene takes the edited media (between updates).
  void applyEditedMedia();

  Scene scene_;
  Camera sceneCamera_;
  std::unique_ptr<OfflineScene> offline_;  ///< over scene_, rebuilt when its geometry or lights change
  std::vector<glm::vec3> lightOffsets_;
  std::vector<float> lightScales_;
  std::string sceneError_, mediaError_;
  std::vector<Medium> media_;  ///< media(); scene_.media until applyEditedMedia()
  bool mediaPending_ = false;

  Settings settings_;
  bool fitPreview_ = true;
  float previewScale_ = 0.4f;
  glm::vec2 displaySize_{1280.0f, 720.0f};
  Method offlineMethod_ = Method::Reference;  ///< what the offline result's staleness is judged for
  Method chosenOfflineMethod_ = Method::Vrl;
  Staleness stale_ = Staleness::all();
  VplSet vpls_;
  /// Over vpls_ and offline_; made again with either.
  std::unique_ptr<RepresentativeLights> representatives_;
  /// A copy of the representatives the preview gathers, when previewReduced_ (an update under way keeps its set
  /// while the VPLs or the scene are made anew).
  VplSet previewSet_;
  bool previewReduced_ = false;
  int vplGenerations_ = 0;
  bool vslRadiiStale_ = false;
  double clampEnergyRemoved_ = -1.0;
  bool clampEnergyStale_ = true;
  std::vector<bool> vplSeen_;
  bool vplSeenStale_ = true;

  std::unique_ptr<PreviewRenderer> preview_;  ///< made by the first update
  CoarsePreview coarse_;
  PreviewTimings timings_, lastPassMs_;
  ChangeTimer changeTimer_;
  Image previewLinear_, residual_;
  std::string previewError_;
  bool previewUpdating_ = false;
  float previewProgress_ = 1.0f;
  /// What the update under way renders (the settings and camera when it started), when it started (s), what the
  /// last finished one took from its start to its image (ms), and how many have finished.
  Settings updateSettings_;
  Camera updateCamera_;
  double updateStart_ = 0.0, lastUpdateMs_ = 0.0;
  /// The coarse image's share of the update under way, and the last finished update's time without it (ms).
  double updateCoarseMs_ = 0.0, lastFullUpdateMs_ = 0.0;
  /// What the update under way redoes (toString(Staleness)), and the last full-size time of each such update (ms).
  std::string updateKind_;
  std::map<std::string, double> fullUpdateMsByKind_;
  int updatesFinished_ = 0;
  /// The preview invalidation an edit asks for, applied when the next update starts.
  LightEdit pendingPreviewInvalidation_ = LightEdit::None;

  OfflineJob job_;
  Image offlineImage_;
  Method offlineImageMethod_ = Method::Reference;
  bool offlineStale_ = false;
  double offlineSeconds_ = 0.0, offlineClampEnergy_ = 0.0;
  Image cutSize_;
  CutSizeSummary cutSummary_;
  std::map<std::string, OfflineTimeEstimate> offlineEstimates_;  ///< per scene file: throughput of its last renders
  Settings offlineJobSettings_;                                  ///< what the running (or last) offline job renders
  std::size_t offlineJobVpls_ = 0;

  std::vector<ChartPoint> chart_;
  bool chartPending_ = false;

  CameraController camera_;
  ViewOptions view_;
  bool displayDirty_ = true;
  const TeachingPreset* activePreset_ = nullptr;
  PresetOffline pendingOffline_ = PresetOffline::None;  ///< started once the preset's VPLs exist
  float animationPhase_ = 0.0f;
  WorkCounters mark_;
};

}  // namespace vplab::ui
