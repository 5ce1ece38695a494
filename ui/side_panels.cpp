#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <utility>

#include "renderer/image/image_io.h"
#include "renderer/image/metrics.h"
#include "renderer/offline/render_methods.h"
#include "renderer/settings_json.h"
#include "ui/editor_panels.h"
#include "ui/layout.h"
#include "ui/media_panel.h"

namespace vplab::ui {

namespace {

/// "850 ms", "12 s", "3 min 20 s".
std::string formatSeconds(double seconds) {
  char text[32];
  if (seconds < 1.0)
    std::snprintf(text, sizeof text, "%.0f ms", seconds * 1e3);
  else if (seconds < 120.0)
    std::snprintf(text, sizeof text, "%.0f s", std::ceil(seconds));
  else
    std::snprintf(text, sizeof text, "%.0f min %.0f s", std::floor(seconds / 60.0),
                  std::fmod(std::ceil(seconds), 60.0));
  return text;
}

const ImVec4 kErrorColour(1.0f, 0.4f, 0.4f, 1.0f);

void drawOfflineSection(EditorState& state) {
  Settings next = state.settings();
  if (drawOfflineSettingsPanel(next)) state.requestSettings(next);
  OfflineJob& job = state.job();
  if (job.running()) {
    double left = job.secondsLeft();
    char overlay[32] = "";
    if (left >= 0.0) std::snprintf(overlay, sizeof(overlay), "%.0f s left", std::ceil(left));
    ImGui::ProgressBar(job.progress(), ImVec2(180.0f, 0.0f), overlay[0] ? overlay : nullptr);
    ImGui::SameLine();
    if (ImGui::Button("Cancel")) job.cancel();
    ImGui::Text("%s: %.1f s (%d spp so far)", toString(job.method()), job.seconds(), job.samplesPerPixel());
  } else {
    if (ImGui::Button("Render reference (O)")) state.startOffline(OfflineRequest::Reference);
    ImGui::SameLine();
    if (ImGui::Button("Render exact VPL")) state.startOffline(OfflineRequest::Exact);
    // Any other method of the table; the media methods matter in a scene with media (without, vpl-abc and vrl are
    // the plain VPL render).
    if (ImGui::BeginCombo("##method", toString(state.offlineMethod()))) {
      for (const RenderMethod& m : renderMethods())
        if (m.id != Method::Reference && ImGui::Selectable(toString(m.id), m.id == state.offlineMethod()))
          state.setOfflineMethod(m.id);
      ImGui::EndCombo();
    }
    if (ImGui::IsItemHovered()) {
      const RenderMethod& m = renderMethod(state.offlineMethod());
      ImGui::SetTooltip("%s (%s):\n%s", m.label, m.citation, m.summary);
    }
    ImGui::SameLine();
    if (ImGui::Button("Render")) state.startOffline(OfflineRequest::Chosen);
    const Method exact = exactCounterpartOf(state.settings());
    auto seconds = [](double s) { return s < 0.0 ? std::string("?") : "~" + formatSeconds(s); };
    ImGui::TextDisabled("estimated: reference %s, %s %s, %s %s",
                        seconds(state.offlineEstimate(Method::Reference)).c_str(), toString(exact),
                        seconds(state.offlineEstimate(exact)).c_str(), toString(state.offlineMethod()),
                        seconds(state.offlineEstimate(state.offlineMethod())).c_str());
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip(
          "From the throughput of the last render of each kind on this scene (? before the first):\n"
          "pixels x spp for the reference, x VPLs (x VSL or VRL samples) for a VPL render.");
    if (!state.offlineImage().empty())
      ImGui::Text("%s%s: %d spp in %.2f s%s", toString(state.offlineImageMethod()),
                  job.cancelled() ? " (cancelled)" : "", job.samplesPerPixel(), state.offlineSeconds(),
                  state.offlineStale() ? "  STALE" : "");
    if (!state.offlineImage().empty() && job.nonFiniteSamples() > 0)
      ImGui::TextColored(kErrorColour, "%llu NaN/Inf samples left out",
                         static_cast<unsigned long long>(job.nonFiniteSamples()));
    if (!job.error().empty()) ImGui::TextColored(kErrorColour, "%s", job.error().c_str());
  }
  const Image& offline = state.offlineImage();
  const Image& preview = state.previewImage();
  if (!offline.empty() && !preview.empty() && offline.width == preview.width && offline.height == preview.height) {
    ImageMetrics m = compareImages(preview, offline);
    ImGui::Text("preview vs offline: relMSE %.4g, energy %.3f", m.relMse, m.energyRatioOverall);
  }
}

void drawChartSection(EditorState& state, PanelState& panels) {
  const int currentPoint = findChartPoint(state.chart(), state.settings());
  int clicked = -1;
  if (panels.chartWindowOpen) {
    // A resizable window of its own, shown whether or not the panel's section is open; the chart fills it, leaving
    // room for the legend.
    ImGui::SetNextWindowSize(ImVec2(720.0f, 480.0f), ImGuiCond_FirstUseEver);
    if (ImGui::Begin("Speed vs accuracy chart", &panels.chartWindowOpen)) {
      ImVec2 room = ImGui::GetContentRegionAvail();
      clicked = drawSpeedAccuracyChart(state.chart(), currentPoint, room.x,
                                       room.y - 3.0f * ImGui::GetFrameHeightWithSpacing());
    }
    ImGui::End();
  }
  if (ImGui::CollapsingHeader("Speed vs accuracy", ImGuiTreeNodeFlags_DefaultOpen)) {
    if (panels.chartWindowOpen)
      ImGui::TextDisabled("The chart is in its own window.");
    else
      clicked = drawSpeedAccuracyChart(state.chart(), currentPoint, kRightPanelWidth - 24.0f, 240.0f);
    if (ImGui::SmallButton(panels.chartWindowOpen ? "dock chart" : "enlarge chart"))
      panels.chartWindowOpen = !panels.chartWindowOpen;
    ImGui::SameLine();
    if (ImGui::SmallButton("clear chart")) state.clearChart();
    // The last converged change: each pass's GPU time summed over the frames it took; a pass it did not re-run is
    // marked cached (its time when it last ran).
    const ChangeTimer& timer = state.changeTimer();
    const PreviewTimings& t = timer.lastPasses();
    const PreviewTimings& last = state.lastPassMs();
    std::vector<PassTiming> passes = {
        {"G-buffer", t.gbufferMs, last.gbufferMs},
        {"light shadows (CPU)", t.directShadowMs, last.directShadowMs},
        {"direct", t.directMs, last.directMs},
        {"VPL shadows (CPU)", t.vplShadowMs, last.vplShadowMs},
        {"gather", t.gatherMs, last.gatherMs},
        {"media", t.mediaMs, last.mediaMs},
        {"SSBC", t.ssbcMs, last.ssbcMs},
        {"VPL generation (CPU)", timer.lastVplGenerationMs(), state.vpls().stats.generationSeconds * 1e3}};
    if (timer.lastMs() >= 0.0)
      ImGui::TextDisabled("last change, %d frame%s; ms per pass (GPU, or CPU where marked):", timer.lastFrames(),
                          timer.lastFrames() == 1 ? "" : "s");
    drawPassTimings(passes);
    // Beside the timings: the preview's representatives (past previewRepresentatives VPLs) and the last lightcuts
    // render's cuts (the cut-size view maps them).
    const RepresentativeStats reps = state.representativeStats();
    if (reps.representatives < reps.vpls)
      ImGui::TextDisabled("preview: %zu representatives of %zu VPLs (cut %.1f ms, %zu moved)", reps.representatives,
                          reps.vpls, reps.selectSeconds * 1e3, reps.moved);
    const CutSizeSummary& cuts = state.cutSummary();
    if (cuts.pixels > 0)
      ImGui::TextDisabled("lightcuts: cut %.0f nodes mean, p95 %.0f, max %.0f; %.1f %% at lightcutMax", cuts.mean,
                          cuts.p95, cuts.max, 100.0 * cuts.atMax);
  }
  if (clicked >= 0 && clicked < static_cast<int>(state.chart().size()))
    state.changeSettings(state.chart()[static_cast<std::size_t>(clicked)].settings);
}

void drawFilesSection(EditorState& state, PanelState& panels) {
  auto attempt = [&](const auto& action) {
    try {
      panels.ioMessage = action();
    } catch (const std::exception& e) {
      panels.ioMessage = e.what();
    }
  };
  ImGui::InputText("settings", &panels.settingsPath);
  if (ImGui::Button("Save settings"))
    attempt([&] {
      saveSettingsFile(panels.settingsPath, state.settings());
      return "saved " + panels.settingsPath;
    });
  ImGui::SameLine();
  if (ImGui::Button("Load settings"))
    attempt([&] {
      Settings next = state.settings();
      loadSettingsFile(panels.settingsPath, next);
      state.requestSettings(next);
      return "loaded " + panels.settingsPath;
    });
  // Next to the scene file; opening the scene again (editor or CLI) applies it.
  if (ImGui::Button("Save lights and media")) attempt([&] { return "saved " + state.saveSidecar(); });
  ImGui::InputText("image", &panels.exportPath);
  auto exportImage = [&](const Image& image) {
    attempt([&] {
      if (image.empty()) throw std::runtime_error("nothing to export yet");
      writeImage(panels.exportPath, image, state.settings().exposure);
      return "wrote " + panels.exportPath;
    });
  };
  if (ImGui::Button("Export preview")) exportImage(state.previewImage());
  ImGui::SameLine();
  if (ImGui::Button("Export offline")) exportImage(state.offlineImage());
  ImGui::TextDisabled(".png (tonemapped), .exr or .pfm (linear)");
  if (!panels.ioMessage.empty()) ImGui::TextWrapped("%s", panels.ioMessage.c_str());
}

void beginPanel(const char* title, float x, float width, float itemWidth) {
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  ImGui::SetNextWindowPos(ImVec2(x, 0));
  ImGui::SetNextWindowSize(ImVec2(width, display.y));
  ImGui::Begin(title, nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  ImGui::PushItemWidth(itemWidth);
}

void endPanel() {
  ImGui::PopItemWidth();
  ImGui::End();
}

}  // namespace

void openSceneFromPanel(EditorState& state, PanelState& panels, const std::string& path) {
  if (!state.openScene(path)) return;
  panels.pathInput = path;
  panels.recent.erase(std::remove(panels.recent.begin(), panels.recent.end(), path), panels.recent.end());
  panels.recent.insert(panels.recent.begin(), path);
}

void openDroppedFile(EditorState& state, PanelState& panels, const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension != ".vdb") {
    openSceneFromPanel(state, panels, path);
    return;
  }
  panels.media.vdbPath = path;
  panels.revealMedia = true;
  std::vector<Medium> media = state.media();
  if (openVdb(state.scene(), media, panels.media, path)) state.editMedia(media);
}

void drawLeftPanel(EditorState& state, PanelState& panels) {
  beginPanel("Controls", 0.0f, kLeftPanelWidth, 170.0f);
  if (ImGui::CollapsingHeader("Scene", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::InputText("##path", &panels.pathInput);
    ImGui::SameLine();
    if (ImGui::Button("Open")) openSceneFromPanel(state, panels, panels.pathInput);
    if (!state.sceneError().empty()) ImGui::TextColored(kErrorColour, "%s", state.sceneError().c_str());
    if (!panels.recent.empty() && ImGui::BeginCombo("recent", "recent files")) {
      for (const std::string& r : panels.recent)
        if (ImGui::Selectable(r.c_str())) {
          std::string path = r;  // opening reorders the list
          openSceneFromPanel(state, panels, path);
          break;
        }
      ImGui::EndCombo();
    }
    ImGui::TextDisabled("or drop a .gltf/.glb on the window (a .vdb: smoke, see Media)");
    drawSceneInfo(state.scene());
  }
  if (ImGui::CollapsingHeader("Camera and lights")) {
    if (ImGui::Button("Reset camera (F)")) state.resetCamera();
    ImGui::TextDisabled("drag: orbit, right drag: pan, wheel: zoom, WASD/QE: fly");
    state.applyLightEdit(drawLightsPanel(state.sceneForLightsPanel(), state.lightOffsets(), state.lightScales()));
    ImGui::Checkbox("animate light", &state.animateLight);
    ImGui::SameLine();
    ImGui::Checkbox("new seed every frame", &state.reseedEveryFrame);
  }
  if (std::exchange(panels.revealMedia, false)) ImGui::SetNextItemOpen(true);
  if (ImGui::CollapsingHeader("Media", state.media().empty() ? 0 : ImGuiTreeNodeFlags_DefaultOpen)) {
    std::vector<Medium> media = state.media();
    if (drawMediaPanel(state.scene(), media, state.mediaError(), panels.media)) state.editMedia(media);
  }
  if (ImGui::CollapsingHeader("Many lights", ImGuiTreeNodeFlags_DefaultOpen)) {
    Settings next = state.settings();
    const std::size_t triangles = state.scene().triangles.size(), vplCount = state.vpls().vpls.size();
    if (drawManyLightPanel(next, state.vpls().stats, state.clampEnergyRemoved(),
                           resolveVisibility(next.visibility, triangles, vplCount), state.scene().geometryBounds.diagonal()))
      state.changeSettings(next);
    if (!state.offlineImage().empty() && renderMethod(state.offlineImageMethod()).usesClampBound) {
      ImGui::TextDisabled("exact render: clamp removed %.1f %% (all pixels)", 100.0 * state.offlineClampEnergy());
      if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "Measured by the exact VPL render over every pixel sample: the luminance its clamped VPL sum\n"
            "lost against the unclamped one, of the VPL (indirect) light.");
    }
  }
  endPanel();
}

void drawRightPanel(EditorState& state, PanelState& panels) {
  beginPanel("Analysis", ImGui::GetIO().DisplaySize.x - kRightPanelWidth, kRightPanelWidth, 180.0f);
  if (ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) {
    ViewOptions& view = state.viewForEditing();
    int mode = static_cast<int>(view.view);
    const char* names[] = {"preview", "reference", "split", "difference", "SSBC residual", "VPLs", "cut size"};
    if (ImGui::Combo("view (1-7)", &mode, names, 7)) state.setView(static_cast<ViewMode>(mode));
    bool fit = state.fitPreview();
    if (ImGui::Checkbox("fit preview to the view", &fit)) state.setFitPreview(fit);
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip(
          "The image size follows the view area times the resolution scale; off: the offline\n"
          "panel's image size, shown at integer zoom.");
    float scale = state.previewScale();
    if (state.fitPreview() &&
        ImGui::SliderFloat("resolution scale", &scale, 0.1f, 1.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp))
      state.setPreviewScale(scale);
    bool coarseFirst = !std::isinf(state.coarseFirstAfterMs);
    if (ImGui::Checkbox("coarse image first", &coarseFirst))
      state.coarseFirstAfterMs = coarseFirst ? 100.0 : std::numeric_limits<double>::infinity();
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip(
          "A change whose update took over 100 ms last time shows its new state at a quarter of the\n"
          "pixels first, then the full image (about a quarter later than without it).");
    if (view.view == ViewMode::Split && ImGui::SliderFloat("divider", &view.divider, 0.0f, 1.0f)) state.viewChanged();
    if (view.view == ViewMode::Difference) {
      if (ImGui::RadioButton("relative error", view.relativeDifference))
        view.relativeDifference = true, state.viewChanged();
      ImGui::SameLine();
      if (ImGui::RadioButton("signed", !view.relativeDifference)) view.relativeDifference = false, state.viewChanged();
      ImGui::TextDisabled(view.relativeDifference ? "(I - R)^2 / (R^2 + 0.01), I preview, R offline"
                                                  : "I - R: red too bright, blue too dark");
    }
    if (view.view == ViewMode::VplOverlay) ImGui::Checkbox("show rejected candidates", &view.showRejected);
    ImGui::Checkbox("show medium boxes", &view.showMediumBoxes);
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("Outlines each medium box over the image: fog, or the bounds of a density grid's smoke.");
  }
  if (ImGui::CollapsingHeader("Offline pass", ImGuiTreeNodeFlags_DefaultOpen)) drawOfflineSection(state);
  drawChartSection(state, panels);
  if (ImGui::CollapsingHeader("Teaching presets")) {
    ImGui::TextDisabled("The explanation is shown above the view.");
    for (const TeachingPreset& p : teachingPresets())
      if (ImGui::Button(p.name.c_str(), ImVec2(kRightPanelWidth - 30.0f, 0.0f))) state.applyPreset(p);
  }
  if (ImGui::CollapsingHeader("Files")) drawFilesSection(state, panels);
  if (ImGui::CollapsingHeader("Help (H)") || panels.showHelp) {
    ImGui::TextWrapped(
        "Mouse: left drag orbit, right/middle drag pan, wheel zoom; in split view drag the divider.\n"
        "Keys: WASD fly, Q/E down/up, F reset camera, 1-7 views, O render reference, Esc cancel offline, "
        "H help.\nChanging b re-gathers only; moving the camera never regenerates VPLs; moving a light or editing a "
        "medium does.");
  }
  endPanel();
}

}  // namespace vplab::ui
