#include "ui/editor_state.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "renderer/core/atomic_file.h"
#include "renderer/core/fnv1a.h"
#include "renderer/core/sampling.h"
#include "renderer/image/metrics.h"
#include "renderer/offline/render_methods.h"
#include "renderer/scene/brdf_params.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/lights_json.h"
#include "renderer/scene/staging.h"
#include "renderer/settings_json.h"
#include "renderer/vpl/vpl_contribution.h"
#include "renderer/vpl/vpl_generation.h"
#include "renderer/vpl/vpl_importance.h"
#include "ui/layout.h"
#include "ui/vpl_overlay.h"

namespace vplab::ui {

namespace {

CameraController controllerFor(const Scene& scene, const Camera& camera) {
  return CameraController(camera, glm::length(scene.bounds.center() - camera.position), scene.bounds.diagonal());
}

}  // namespace

EditorState::EditorState(const std::string& scenePath, const Settings& settings, bool fitPreview, float previewScale)
    : settings_(settings), fitPreview_(fitPreview), previewScale_(previewScale) {
  requireValidSettings(settings_);
  scene_ = loadScene(scenePath);
  stageScene(scene_, settings_.stage);
  applyLightsSidecar(scene_);
  resolveClampBound(settings_, scene_.geometryBounds.diagonal());
  sceneCamera_ = scene_.camera;
  media_ = scene_.media;
  rebuildAcceleration();
  camera_ = controllerFor(scene_, sceneCamera_);
}

EditorState::~EditorState() {
  job_.cancel();
}

// --- scene, lights and media --------------------------------------------------------------------------------------

bool EditorState::openScene(const std::string& path) {
  Scene loaded;
  try {
    loaded = loadScene(path);
    stageScene(loaded, settings_.stage);
    applyLightsSidecar(loaded);
  } catch (const std::exception& e) {
    sceneError_ = e.what();  // a bad file leaves the current scene in place
    return false;
  }
  sceneError_.clear();
  mediaError_.clear();
  job_.cancel();
  activePreset_ = nullptr;  // a preset that wants it sets itself again after this
  pendingOffline_ = PresetOffline::None;
  scene_ = std::move(loaded);
  resolveClampBound(settings_, scene_.geometryBounds.diagonal());
  sceneCamera_ = scene_.camera;
  media_ = scene_.media;
  mediaPending_ = false;
  rebuildAcceleration();
  camera_ = controllerFor(scene_, sceneCamera_);
  lightOffsets_.clear();
  lightScales_.clear();
  // An update of the old scene is abandoned: the next one starts from scratch.
  invalidatePreviews(&PreviewRenderer::invalidateScene);
  fullUpdateMsByKind_.clear();  // another scene's costs predict nothing here
  lastFullUpdateMs_ = 0.0;
  previewUpdating_ = false;
  pendingPreviewInvalidation_ = LightEdit::None;
  markStale(Staleness::all());
  offlineImage_ = Image();
  chart_.clear();
  return true;
}

void EditorState::rebuildAcceleration() {
  representatives_.reset();  // it holds the old OfflineScene
  stale_.representatives = true;
  offline_.reset();
  offline_ = std::make_unique<OfflineScene>(scene_);
}

void EditorState::editLight(std::size_t index, const glm::vec3& offset, float scale) {
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

void EditorState::applyLightEdit(LightEdit edit) {
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

bool EditorState::editMedia(const std::vector<Medium>& next) {
  if (std::string problem = mediaProblem(next); !problem.empty()) {
    mediaError_ = problem;
    return false;
  }
  mediaError_.clear();
  const Staleness s = staleAfterMediumEdit(media_, next);
  media_ = next;
  mediaPending_ = true;
  markStale(s);
  if (s.anyPreview()) chartPending_ = true;
  return true;
}

void EditorState::applyEditedMedia() {
  if (!mediaPending_) return;
  mediaPending_ = false;
  scene_.media = media_;
  // The BVH reads scene_.media where it traces; the light sampler sizes a directional light's disk to cover them.
  offline_->punctualLightsChanged();
}

std::string EditorState::saveSidecar() {
  const std::string path = lightsSidecarPath(scene_.sourcePath);
  Scene edited = scene_;
  edited.media = media_;
  saveLightsFile(path, edited);
  return path;
}

// --- camera -------------------------------------------------------------------------------------------------------

void EditorState::cameraMoved() {
  markStale(staleAfterCameraMove());
}

void EditorState::resetCamera() {
  camera_ = controllerFor(scene_, sceneCamera_);
  cameraMoved();
}

// --- settings -----------------------------------------------------------------------------------------------------

void EditorState::changeSettings(const Settings& requested) {
  if (!validateSettings(requested).empty()) return;
  Settings next = requested;
  resolveClampBound(next, scene_.geometryBounds.diagonal());
  Staleness s = staleAfterSettingsChange(settings_, next, offlineMethod_);
  if (!s.vpls && (next.vslRadius != settings_.vslRadius || next.vslRadiusFromDensity != settings_.vslRadiusFromDensity))
    vslRadiiStale_ = true;
  settings_ = next;
  markStale(s);
  if (s.anyPreview()) chartPending_ = true;
}

void EditorState::requestSettings(const Settings& next) {
  if (next.width != settings_.width || next.height != settings_.height) fitPreview_ = false;  // asked for a size
  changeSettings(next);
}

void EditorState::setPreviewScale(float scale) {
  fitPreview_ = true;
  previewScale_ = std::clamp(scale, 0.05f, 1.0f);
}

void EditorState::setDisplaySize(float width, float height) {
  displaySize_ = {width, height};
}

glm::ivec2 EditorState::fittedPreviewSize(bool presetBox) const {
  const float width = displaySize_.x - kLeftPanelWidth - kRightPanelWidth - kViewMarginX;
  const float height = displaySize_.y - (presetBox ? kPresetBoxHeight : 0.0f) - kViewMarginY;
  return {std::clamp(static_cast<int>(std::lround(width * previewScale_)), 16, 2048),
          std::clamp(static_cast<int>(std::lround(height * previewScale_)), 16, 2048)};
}

void EditorState::fitPreviewToView() {
  if (!fitPreview_) return;
  const glm::ivec2 size = fittedPreviewSize(activePreset_ != nullptr);
  if (size.x == settings_.width && size.y == settings_.height) return;
  Settings next = settings_;
  next.width = size.x;
  next.height = size.y;
  changeSettings(next);
}

// --- view ---------------------------------------------------------------------------------------------------------

void EditorState::viewChanged() {
  if (view_.view == ViewMode::SsbcResidual) stale_.gather = true;  // the residual is read back on render
  displayDirty_ = true;
}

void EditorState::setView(ViewMode mode) {
  view_.view = mode;
  viewChanged();
}

bool EditorState::takeDisplayDirty() {
  const bool dirty = displayDirty_;
  displayDirty_ = false;
  return dirty;
}

// --- work ---------------------------------------------------------------------------------------------------------

void EditorState::markStale(const Staleness& s) {
  if (s.anyPreview()) changeTimer_.changed(steadySeconds());
  stale_ |= s;
  if (s.offline && !offlineImage_.empty()) offlineStale_ = true;
  if (s.vpls || s.gather) clampEnergyStale_ = true;
  if (s.vpls || s.gather) vplSeenStale_ = true;  // gather: the camera may have moved
  displayDirty_ = true;
}

void EditorState::invalidatePreviews(void (PreviewRenderer::*what)()) {
  if (preview_) (preview_.get()->*what)();
  coarse_.invalidate(what);
}

void EditorState::regenerateVpls() {
  // Importance-driven generation (rejection, bidirectional, Metropolis) measures importance from the current view.
  scene_.camera = camera_.camera();
  vpls_ = generateVpls(*offline_, settings_);
  changeTimer_.vplsGenerated(vpls_.stats.generationSeconds * 1e3);
  ++vplGenerations_;
  vslRadiiStale_ = false;
  representatives_.reset();
  stale_.representatives = true;
  invalidatePreviews(&PreviewRenderer::invalidateVpls);
}

void EditorState::chooseRepresentatives() {
  // The tree is built once per VPL set (and scene); a new count of representatives that turns the reduction on or off
  // needs it made again.
  if (!representatives_ || representatives_->reduces() != previewReducesVpls(vpls_, updateSettings_))
    representatives_ = std::make_unique<RepresentativeLights>(*offline_, vpls_, updateSettings_);
  const VplSet& chosen = representatives_->select(updateCamera_, updateSettings_);
  previewReduced_ = &chosen != &vpls_;
  if (previewReduced_ && chosen.id != previewSet_.id) previewSet_ = chosen;
}

void EditorState::measureClampEnergy() {
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
      if (vpl.inMedium) continue;  // no geometry term to clamp at its end
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

void EditorState::measureVplsSeen() {
  vplSeenStale_ = false;
  vplSeen_ = vplsSeenByCamera(offline_->embree(), camera_.camera(), vpls_.vpls);
}

void EditorState::updateWork(double budgetMs) {
  // Changes made while an update is under way wait for it (their flags stay in stale_): every finished image is the
  // one `vplab preview` gives for the settings, camera and VPLs its update started with, and a light drag or an orbit
  // shows a new image each time an update finishes instead of restarting the update every frame.
  const bool startUpdate = !previewUpdating_ && stale_.anyPreview();
  if (!previewUpdating_) {
    applyEditedMedia();
    if (stale_.vpls) regenerateVpls();
    if (vslRadiiStale_) {
      std::vector<float> radii = vslRadii(vpls_.vpls, settings_, scene_.bounds.diagonal());
      for (std::size_t i = 0; i < radii.size(); ++i) vpls_.vpls[i].radius = radii[i];
      representatives_.reset();  // its representatives copy the radii
      stale_.representatives = true;
      invalidatePreviews(&PreviewRenderer::invalidateVpls);
      vslRadiiStale_ = false;
    }
    if (clampEnergyStale_) measureClampEnergy();
  }
  if (!previewUpdating_ && view_.view == ViewMode::VplOverlay && vplSeenStale_) measureVplsSeen();
  if (pendingOffline_ != PresetOffline::None) {
    startOffline(pendingOffline_ == PresetOffline::Reference  ? OfflineRequest::Reference
                 : pendingOffline_ == PresetOffline::ExactVpl ? OfflineRequest::Exact
                                                              : OfflineRequest::Chosen);
    pendingOffline_ = PresetOffline::None;
  }
  if (startUpdate) {
    if (pendingPreviewInvalidation_ == LightEdit::Geometry) invalidatePreviews(&PreviewRenderer::invalidateScene);
    if (pendingPreviewInvalidation_ == LightEdit::Punctual) invalidatePreviews(&PreviewRenderer::invalidateLights);
    pendingPreviewInvalidation_ = LightEdit::None;
    updateSettings_ = settings_;
    updateCamera_ = camera_.camera();
    updateStart_ = steadySeconds();
    if (stale_.representatives || !representatives_) chooseRepresentatives();
  }
  if (!startUpdate && !previewUpdating_) return;
  try {
    if (!preview_) preview_ = std::make_unique<PreviewRenderer>();  // the first update: GL is current from here on
    // Long work is split across frames (PreviewRenderer::render's budget): the last finished image stays on screen
    // with "updating n %" until the new one is complete, which is then the image `vplab preview` gives.
    // A change whose last update took longer than coarseFirstAfterMs shows the new state at a quarter of the pixels
    // first (CoarsePreview), and the full-size update goes on with what is left of this frame's budget.
    double fullBudgetMs = budgetMs;
    // What the update is predicted to take: the last update that redid the same stages, else the last update.
    bool slow = false;
    if (startUpdate) {
      updateCoarseMs_ = 0.0;
      updateKind_ = toString(stale_);
      const auto same = fullUpdateMsByKind_.find(updateKind_);
      slow = (same != fullUpdateMsByKind_.end() ? same->second : lastFullUpdateMs_) > coarseFirstAfterMs;
    }
    if (slow && view_.view != ViewMode::SsbcResidual) {
      try {
        previewLinear_ = coarse_.render(scene_, previewVpls(), updateSettings_, updateCamera_);
        updateCoarseMs_ = coarse_.lastMs();
        fullBudgetMs = std::max(1.0, budgetMs - updateCoarseMs_);
        changeTimer_.coarseShown(steadySeconds());
        displayDirty_ = true;
      } catch (const std::exception&) {
        // The full-size render meets the same problem and reports it below.
      }
    }
    timings_ = preview_->render(scene_, previewVpls(), updateSettings_, updateCamera_, fullBudgetMs);
    changeTimer_.rendered(steadySeconds(), timings_);
    previewUpdating_ = !timings_.complete;
    previewProgress_ = timings_.progress;
    if (timings_.complete) {
      previewLinear_ = preview_->readLinear();
      residual_ = view_.view == ViewMode::SsbcResidual ? preview_->readLinear(PreviewOutput::Residual) : Image();
      lastUpdateMs_ = (steadySeconds() - updateStart_) * 1e3;
      lastFullUpdateMs_ = lastUpdateMs_ - updateCoarseMs_;
      fullUpdateMsByKind_[updateKind_] = lastFullUpdateMs_;
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
  keep(lastPassMs_.mediaMs, timings_.mediaMs);
  keep(lastPassMs_.ssbcMs, timings_.ssbcMs);
  if (startUpdate) {
    const bool offline = stale_.offline;
    stale_ = Staleness{};
    stale_.offline = offline;
  }
  if (!previewUpdating_) {
    displayDirty_ = true;
    if (chartPending_) addChartPoint();
  }
}

void EditorState::finishWork() {
  do updateWork(60.0);
  while ((previewUpdating_ || stale_.anyPreview()) && previewError_.empty());
}

bool EditorState::busy() const {
  return stale_.anyPreview() || previewUpdating_ || job_.running() || animateLight;
}

WorkCounters EditorState::counters() const {
  if (!preview_) return {vplGenerations_, 0, 0};
  return {vplGenerations_, preview_->counters().vplShadowMaps, preview_->counters().gather};
}

void EditorState::mark() {
  finishWork();  // what is stale now belongs before the mark
  mark_ = counters();
}

WorkCounters EditorState::sinceMark() {
  finishWork();
  const WorkCounters n = counters();
  return {n.vplGenerations - mark_.vplGenerations, n.vplShadowMaps - mark_.vplShadowMaps, n.gathers - mark_.gathers};
}

// --- offline pass -------------------------------------------------------------------------------------------------

void EditorState::startOffline(OfflineRequest request) {
  // The offline pass renders what the editor shows; a media edit made while an update runs reaches the preview with
  // the next update.
  if (!previewUpdating_) applyEditedMedia();
  offlineMethod_ = request == OfflineRequest::Reference ? Method::Reference
                   : request == OfflineRequest::Exact   ? exactCounterpartOf(settings_)
                                                        : chosenOfflineMethod_;
  job_.start(scene_, camera_.camera(), vpls_, settings_, offlineMethod_);
  offlineJobSettings_ = settings_;
  offlineJobVpls_ = vpls_.vpls.size();
  offlineStale_ = false;
}

void EditorState::pollOffline() {
  if (std::optional<Image> image = job_.takeImage()) {
    offlineImage_ = std::move(*image);
    offlineImageMethod_ = job_.method();
    const ViewMode v = view_.view;
    displayDirty_ |= v != ViewMode::Preview && v != ViewMode::VplOverlay && v != ViewMode::SsbcResidual;
  }
  if (!job_.takeFinished()) return;
  offlineSeconds_ = job_.seconds();
  offlineClampEnergy_ = job_.clampEnergyRemoved();
  const bool completed = !job_.cancelled() && job_.error().empty();
  // A lightcuts render keeps its cut sizes until the next one (the cut-size view and the cut statistics).
  if (completed && (job_.method() == Method::Lightcuts || job_.method() == Method::LightcutsKK)) {
    cutSize_ = job_.cutSize();
    cutSummary_ = summarizeCutSizes(cutSize_, offlineJobSettings_.lightcutMax);
  }
  if (completed)
    offlineEstimates_[scene_.sourcePath].record(
        job_.method(), offlineRenderSettings(offlineJobSettings_, job_.method()), offlineJobVpls_, job_.seconds());
  if (completed && job_.method() == Method::Reference) {
    // A new reference: the chart's errors were measured against the old one.
    chart_.clear();
    chartPending_ = true;
    addChartPoint();
  }
  displayDirty_ = true;
}

double EditorState::offlineEstimate(Method method) const {
  auto it = offlineEstimates_.find(scene_.sourcePath);
  if (it == offlineEstimates_.end()) return -1.0;
  return it->second.estimate(method, offlineRenderSettings(settings_, method),
                             method == Method::Reference ? 0 : vpls_.vpls.size());
}

// --- chart --------------------------------------------------------------------------------------------------------

void EditorState::addChartPoint() {
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

// --- presets and animation ----------------------------------------------------------------------------------------

Settings EditorState::presetSettingsHere(const TeachingPreset& preset) const {
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

bool EditorState::applyPreset(const TeachingPreset& preset) {
  // Always reloaded, even when it is the current scene: a previous preset (or the user) may have moved or scaled
  // lights or edited media, and openScene also resets the camera and drops the offline result and the chart.
  if (!openScene(std::string(VPLAB_ASSET_DIR) + "/scenes/" + preset.scene)) return false;
  changeSettings(presetSettingsHere(preset));
  view_ = ViewOptions{};
  view_.view = preset.view;
  view_.divider = preset.divider;
  view_.relativeDifference = !preset.signedDifference;
  view_.showRejected = preset.showRejected;
  viewChanged();
  animateLight = preset.animateLight;
  reseedEveryFrame = preset.reseedEveryFrame;
  animationPhase_ = 0.0f;
  chosenOfflineMethod_ = preset.offlineMethod;
  pendingOffline_ = preset.offline;
  activePreset_ = &preset;
  return true;
}

std::string EditorState::presetState() const {
  // Hashes keep the line short; each part is named so that a difference says what leaked.
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
  std::string media;
  for (const Medium& m : media_)
    media += vec(m.sigmaA) + vec(m.sigmaS) + std::to_string(m.g) + vec(m.centre()) + vec(m.halfSizes()) +
             m.densityUri + m.densityGridName + std::to_string(m.densityScale);
  const Camera cam = camera_.camera();
  char view[192];
  std::snprintf(view, sizeof view,
                "%s relative=%d rejected=%d boxes=%d divider=%g animate=%d reseed=%d phase=%g offline=%s",
                toString(view_.view), view_.relativeDifference, view_.showRejected, view_.showMediumBoxes,
                view_.divider, animateLight, reseedEveryFrame, animationPhase_, toString(chosenOfflineMethod_));
  return "scene=" + std::filesystem::path(scene_.sourcePath).filename().string() +
         " settings=" + fnv1a64Hex(settingsToJson(settings_)) + " lights=" + fnv1a64Hex(lights) +
         " media=" + fnv1a64Hex(media) +
         " camera=" + fnv1a64Hex(vec(cam.position) + vec(cam.forward) + vec(cam.up) + std::to_string(cam.yfov)) + " " +
         view;
}

void EditorState::animate() {
  if (!animateLight) return;
  if (editableLights(scene_).empty()) return;
  const glm::vec3 offset = lightAnimationStep(animationPhase_, scene_.bounds.diagonal());
  if (reseedEveryFrame) {
    Settings next = settings_;
    next.seed = settings_.seed + 1;
    changeSettings(next);
  }
  editLight(0, offset, 1.0f);
}

}  // namespace vplab::ui
