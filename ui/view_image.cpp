#include "ui/view_image.h"

#include <algorithm>

#include "renderer/image/heatmap.h"
#include "renderer/image/metrics.h"
#include "renderer/image/tonemap.h"

namespace vplab::ui {

namespace {

/// The empty-state message of a view that needs an offline result of the preview's size.
std::string offlineMismatch(const EditorState& state, const std::string& what) {
  const Image& offline = state.offlineImage();
  const Image& preview = state.previewImage();
  if (offline.empty()) return "No offline result yet.\n" + what;
  return "The offline result is " + std::to_string(offline.width) + "x" + std::to_string(offline.height) +
         ", the preview " + std::to_string(preview.width) + "x" + std::to_string(preview.height) +
         ": render it again at this size.\n" + what;
}

ViewImage tonemapped(const Image& image, float exposure) {
  ViewImage v;
  v.width = image.width;
  v.height = image.height;
  v.rgb = tonemapToRgb8(image, exposure);
  return v;
}

ViewImage heatmapView(Heatmap h) {
  ViewImage v;
  v.width = h.width;
  v.height = h.height;
  v.rgb = std::move(h.rgb);
  return v;
}

}  // namespace

ViewImage composeView(const EditorState& state) {
  const ViewOptions& options = state.view();
  const float exposure = state.settings().exposure;
  const Image& previewLinear = state.previewImage();
  const Image& offline = state.offlineImage();
  const bool sameSize =
      !offline.empty() && offline.width == previewLinear.width && offline.height == previewLinear.height;
  ViewImage v;
  switch (options.view) {
    case ViewMode::Preview:
    case ViewMode::VplOverlay:
    case ViewMode::SsbcResidual: {
      const Image& preview = options.view == ViewMode::SsbcResidual ? state.residualImage() : previewLinear;
      if (!preview.empty()) return tonemapped(preview, exposure);
      v.note = options.view == ViewMode::SsbcResidual && state.settings().ssbcSteps == 0 ? "SSBC is off (steps = 0)"
                                                                                         : "no preview image";
      return v;
    }
    case ViewMode::Reference:
      if (!offline.empty()) return tonemapped(offline, exposure);
      v.emptyState =
          "No offline result yet.\nThe reference view shows the offline result (the path-traced reference, "
          "the exact VPL render or a media method) of the current scene, camera and settings.";
      return v;
    case ViewMode::Split: {
      if (!sameSize) {
        v.emptyState = offlineMismatch(state,
                                       "The split view puts the preview left of the divider and the offline "
                                       "result right of it.");
        return v;
      }
      v = tonemapped(previewLinear, exposure);
      const std::vector<uint8_t> right = tonemapToRgb8(offline, exposure);
      const int split = std::clamp(static_cast<int>(options.divider * v.width), 0, v.width);
      for (int y = 0; y < v.height; ++y) {
        const std::size_t row = static_cast<std::size_t>(y) * v.width;
        std::copy(right.begin() + (row + split) * 3, right.begin() + (row + v.width) * 3,
                  v.rgb.begin() + (row + split) * 3);
      }
      return v;
    }
    case ViewMode::Difference: {
      if (!sameSize) {
        v.emptyState =
            offlineMismatch(state, "The difference view maps the preview's error against the offline result.");
        return v;
      }
      HeatmapOptions heat;
      Heatmap h;
      if (options.relativeDifference) {
        heat.colormap = Colormap::Viridis;
        heat.title = "relative error vs offline";  // short: the legend is 256 px wide
        h = renderHeatmap(relativeErrorImage(previewLinear, offline), heat);
      } else {
        heat.colormap = Colormap::Diverging;
        heat.title = "preview - offline";
        h = renderHeatmap(signedDifferenceImage(previewLinear, offline), heat);
      }
      return heatmapView(std::move(h));
    }
    case ViewMode::CutSize: {
      if (state.cutSize().empty()) {
        v.emptyState =
            "No lightcuts render yet.\nThe cut-size view maps how many light-tree nodes each pixel's cut of the last "
            "lightcuts render held (choose lightcuts in the offline panel and render).";
        return v;
      }
      HeatmapOptions heat;
      heat.title = "lightcut size (nodes)";
      heat.minValue = 0.0f;
      return heatmapView(renderHeatmap(state.cutSize(), heat));
    }
  }
  return v;
}

}  // namespace vplab::ui
