#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "evaluation/sweep.h"
#include "renderer/core/sampling.h"
#include "renderer/settings_json.h"
#include "renderer/vpl/generation_methods.h"
#include "ui/editor_panels.h"
#include "ui/layout.h"
#include "ui/vpl_overlay.h"

namespace vplab::ui {

namespace {

/// The view, its size, what the last change cost, this frame's time and the VPL count, at (x, y).
void drawStatusBar(const EditorState& state, double frameMs, float x, float y) {
  // What a change costs is the time until its image is complete, over frames; a single frame says little.
  const ChangeTimer& timer = state.changeTimer();
  char change[96] = "";
  if (timer.pending())
    std::snprintf(change, sizeof change, "updating %d %%, %.0f ms so far",
                  static_cast<int>(100.0f * state.previewProgress()), timer.pendingMs(steadySeconds()));
  else if (timer.lastMs() >= 0.0 && timer.lastHadCoarseImage())
    std::snprintf(change, sizeof change, "last change: coarse image %.0f ms, final %.0f ms (%d frame%s)",
                  timer.lastFirstImageMs(), timer.lastMs(), timer.lastFrames(), timer.lastFrames() == 1 ? "" : "s");
  else if (timer.lastMs() >= 0.0)
    std::snprintf(change, sizeof change, "last change %.0f ms (%d frame%s)", timer.lastMs(), timer.lastFrames(),
                  timer.lastFrames() == 1 ? "" : "s");
  char status[256];
  std::snprintf(status, sizeof status, "%s %dx%d  %s  this frame %.0f ms  %zu VPLs", toString(state.view().view),
                state.settings().width, state.settings().height, change, frameMs, state.vpls().vpls.size());
  ImGui::GetBackgroundDrawList()->AddText(ImVec2(x, y), IM_COL32(200, 200, 200, 255), status);
}

/// The render buttons of the offline pass, or the running job with its cancel button.
void drawRenderButtons(EditorState& state) {
  OfflineJob& job = state.job();
  if (job.running()) {
    ImGui::Text("%s running: %.0f %%", toString(job.method()), 100.0f * job.progress());
    ImGui::SameLine();
    if (ImGui::SmallButton("Cancel")) job.cancel();
    return;
  }
  if (ImGui::Button("Render reference (O)")) state.startOffline(OfflineRequest::Reference);
  ImGui::SameLine();
  if (ImGui::Button("Render exact VPL")) state.startOffline(OfflineRequest::Exact);
}

/// The empty state in the middle of the view area: the message, and the render buttons or the running job.
void drawEmptyState(EditorState& state, const std::string& message, float x, float y, float width, float height) {
  const float boxWidth = std::min(width - 32.0f, 420.0f);
  ImGui::SetNextWindowPos(ImVec2(x + 0.5f * width, y + 0.4f * height), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
  ImGui::SetNextWindowSize(ImVec2(boxWidth, 0.0f));
  ImGui::Begin("##empty", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings |
                   ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoFocusOnAppearing);
  ImGui::PushTextWrapPos(boxWidth - ImGui::GetStyle().WindowPadding.x);
  ImGui::TextUnformatted(message.c_str());
  ImGui::PopTextWrapPos();
  drawRenderButtons(state);
  ImGui::End();
}

/// The active preset's description in a box of kPresetBoxHeight at the top of the view area.
void drawPresetExplanation(EditorState& state, float x, float width) {
  const TeachingPreset& preset = *state.activePreset();
  const bool modified = settingsToJson(state.settings()) != settingsToJson(state.presetSettingsHere(preset));
  ImGui::SetNextWindowPos(ImVec2(x, 0.0f));
  ImGui::SetNextWindowSize(ImVec2(width, kPresetBoxHeight - 4.0f));
  ImGui::Begin("##preset", nullptr,
               ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                   ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
                   ImGuiWindowFlags_NoBringToFrontOnFocus);
  const bool close = ImGui::SmallButton("close explanation");
  if (modified) {
    ImGui::SameLine();
    ImGui::TextDisabled("settings changed since the preset");
  }
  ImGui::TextWrapped("%s", presetDescription(preset).c_str());
  ImGui::End();
  if (close) state.closePreset();
}

/// The editor camera's view of the image at (x0, y0) of w x h image pixels shown at `scale` (window pixels).
struct ViewProjection {
  ViewProjection(const EditorState& state, float x0, float y0, float w, float h, float scale)
      : cam(state.camera().camera()),
        aspect(static_cast<float>(state.settings().width) / static_cast<float>(state.settings().height)),
        x0(x0),
        y0(y0),
        width(w * scale),
        height(h * scale) {}
  /// The window position of normalised device coordinates (projectToImage's).
  ImVec2 toWindow(const glm::vec2& ndc) const {
    return ImVec2(x0 + 0.5f * (ndc.x + 1.0f) * width, y0 + 0.5f * (1.0f - ndc.y) * height);
  }
  /// The window position of p; false when p is behind the near plane or outside the image.
  bool project(const glm::vec3& p, ImVec2& out) const {
    const std::optional<glm::vec2> ndc = projectToImage(cam, aspect, p);
    if (!ndc) return false;
    out = toWindow(*ndc);
    return std::abs(ndc->x) <= 1.0f && std::abs(ndc->y) <= 1.0f;
  }

  Camera cam;
  float aspect, x0, y0, width, height;
};

/// Every medium box's outline over the image (a density grid's box is where its smoke can be), with its name at its
/// top corner; fog and smoke in different colours.
void drawMediumBoxes(const EditorState& state, const ViewProjection& view) {
  ImDrawList* draw = ImGui::GetBackgroundDrawList();
  draw->PushClipRect(ImVec2(view.x0, view.y0), ImVec2(view.x0 + view.width, view.y0 + view.height), true);
  for (const Medium& m : state.media()) {
    const ImU32 colour = m.heterogeneous() ? IM_COL32(255, 170, 80, 220) : IM_COL32(120, 190, 255, 200);
    for (const std::array<glm::vec2, 2>& edge : mediumBoxOutline(m, view.cam, view.aspect))
      draw->AddLine(view.toWindow(edge[0]), view.toWindow(edge[1]), colour, 1.5f);
    ImVec2 label(0.0f, std::numeric_limits<float>::max());
    for (const glm::vec3& c : m.corners()) {
      ImVec2 p;
      if (view.project(c, p) && p.y < label.y) label = p;
    }
    if (label.y < std::numeric_limits<float>::max())
      draw->AddText(ImVec2(label.x + 3.0f, label.y - 16.0f), colour,
                    (m.name + (m.heterogeneous() ? " (density grid)" : "")).c_str());
  }
  draw->PopClipRect();
}

/// The VPLs over the image.
void drawVplOverlay(const EditorState& state, const ViewProjection& view) {
  ImDrawList* draw = ImGui::GetBackgroundDrawList();
  const Settings& settings = state.settings();
  const std::vector<Vpl>& vpls = state.vpls().vpls;
  const float x0 = view.x0, y0 = view.y0;
  float maxFlux = 1e-12f;
  for (const Vpl& v : vpls) maxFlux = std::max(maxFlux, luminance(v.flux));
  // The ring takes the generation method's chart colour (the one its bench rows have), so a screenshot says which
  // method put the VPLs there.
  const unsigned rgb = benchMethodColourRgb(generationVariantOf(settings).name);
  const ImU32 ring = IM_COL32((rgb >> 16) & 0xff, (rgb >> 8) & 0xff, rgb & 0xff, 230);
  const std::vector<bool>& seen = state.vplsSeen();
  const bool seenKnown = seen.size() == vpls.size();
  for (std::size_t i = 0; i < vpls.size(); ++i) {
    const Vpl& v = vpls[i];
    ImVec2 p;
    if (!view.project(v.position, p)) continue;
    // Size by relative power on a log scale, colour by the flux's chromaticity; a VPL the camera does not see
    // (behind a wall, in another room) is a hollow grey ring.
    float rel = std::clamp(luminance(v.flux) / maxFlux, 1e-4f, 1.0f);
    float radius = 1.5f + 4.0f * (1.0f + std::log10(rel) / 4.0f);
    glm::vec3 c = v.flux / std::max({v.flux.r, v.flux.g, v.flux.b, 1e-12f});
    if (!seenKnown || seen[i]) {
      draw->AddCircleFilled(
          p, radius,
          IM_COL32(static_cast<int>(255 * c.r), static_cast<int>(255 * c.g), static_cast<int>(255 * c.b), 230));
      draw->AddCircle(p, radius + 0.5f, ring, 0, 1.5f);
    } else {
      draw->AddCircle(p, radius, IM_COL32(160, 160, 160, 200), 0, 1.5f);
    }
  }
  if (seenKnown && !vpls.empty()) {
    char count[160];
    std::snprintf(count, sizeof count, "the camera sees %zu of %zu VPLs (%.0f %%); hollow rings: hidden",
                  static_cast<std::size_t>(std::count(seen.begin(), seen.end(), true)), vpls.size(),
                  100.0 * seenShare(seen));
    draw->AddText(ImVec2(x0, y0 - 18.0f), IM_COL32(230, 230, 230, 255), count);
  }
  draw->AddText(ImVec2(x0 + 4, y0 + 4), ring, generationVariantOf(settings).label);
  if (state.view().showRejected)
    for (const Vpl& v : state.vpls().rejected) {
      ImVec2 p;
      if (!view.project(v.position, p)) continue;
      draw->AddLine(ImVec2(p.x - 2, p.y - 2), ImVec2(p.x + 2, p.y + 2), IM_COL32(150, 150, 150, 180));
      draw->AddLine(ImVec2(p.x - 2, p.y + 2), ImVec2(p.x + 2, p.y - 2), IM_COL32(150, 150, 150, 180));
    }
}

}  // namespace

void drawView(EditorState& state, const ViewImage& shown, double frameMs, ViewPlacement& placed) {
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  const float areaX = kLeftPanelWidth, areaW = display.x - kLeftPanelWidth - kRightPanelWidth;
  if (state.activePreset()) drawPresetExplanation(state, areaX, areaW);
  // The active preset's explanation sits above the image, which fits in what is left.
  const float areaY = state.activePreset() ? kPresetBoxHeight : 0.0f, areaH = display.y - areaY;
  state.setDisplaySize(display.x, display.y);
  state.fitPreviewToView();
  ImDrawList* draw = ImGui::GetBackgroundDrawList();
  if (!shown.note.empty() || !state.previewError().empty()) {
    std::string note = state.previewError().empty() ? shown.note : "preview error: " + state.previewError();
    draw->AddText(ImVec2(areaX + 12, areaY + 12), IM_COL32(230, 200, 120, 255), note.c_str());
  }
  if (!shown.emptyState.empty() || shown.rgb.empty()) {
    if (!shown.emptyState.empty()) drawEmptyState(state, shown.emptyState, areaX, areaY, areaW, areaH);
    drawStatusBar(state, frameMs, areaX + 8.0f, areaY + areaH - 20.0f);
    return;
  }
  const float w = static_cast<float>(shown.width), h = static_cast<float>(shown.height);
  // A fitted preview fills the view (linear filtering); an explicit size is shown at integer zoom, which keeps
  // preview pixels square and exact (the tests compare them with the headless preview).
  float scale = std::min((areaW - kViewMarginX) / w, (areaH - kViewMarginY) / h);
  if (!state.fitPreview() && scale >= 1.0f) scale = std::floor(scale);
  const float x0 = std::floor(areaX + 0.5f * (areaW - w * scale));
  const float y0 = std::floor(areaY + 0.5f * (areaH - h * scale));
  placed = {x0, y0, w * scale, h * scale, scale};
  // The image itself is blitted before ImGui draws (the window's frame); the overlays below go on top of it.
  const ViewOptions& options = state.view();
  if (options.view == ViewMode::Split && shown.note.empty()) {
    float x = x0 + options.divider * w * scale;
    draw->AddLine(ImVec2(x, y0), ImVec2(x, y0 + h * scale), IM_COL32(255, 255, 255, 200), 1.0f);
    draw->AddText(ImVec2(x0 + 4, y0 + 4), IM_COL32(255, 255, 255, 220), "preview");
    std::string right = std::string(toString(state.offlineImageMethod())) + (state.offlineStale() ? " (stale)" : "");
    draw->AddText(ImVec2(x0 + w * scale - 8 - 7.0f * right.size(), y0 + 4), IM_COL32(255, 255, 255, 220),
                  right.c_str());
  }
  const ViewProjection projection(state, x0, y0, w, h, scale);
  if (options.showMediumBoxes) drawMediumBoxes(state, projection);
  if (options.view == ViewMode::VplOverlay) drawVplOverlay(state, projection);
  drawStatusBar(state, frameMs, areaX + 8.0f, areaY + areaH - 20.0f);
}

}  // namespace vplab::ui
