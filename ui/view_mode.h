#pragma once
// What the editor's main view shows.

namespace vplab::ui {

enum class ViewMode {
  Preview,       ///< the GL preview
  Reference,     ///< the offline result (reference or exact VPL render)
  Split,         ///< preview left of a draggable divider, offline result right
  Difference,    ///< signed or relative-error heatmap of preview against the offline result, with legend
  SsbcResidual,  ///< only the light added by screen-space bias compensation
  VplOverlay,    ///< the preview with the VPLs drawn as points sized and coloured by flux
  CutSize,       ///< heatmap of the last lightcuts render's cut size per pixel, with legend
};

inline constexpr ViewMode kAllViewModes[] = {ViewMode::Preview,    ViewMode::Reference,    ViewMode::Split,
                                             ViewMode::Difference, ViewMode::SsbcResidual, ViewMode::VplOverlay,
                                             ViewMode::CutSize};

inline const char* toString(ViewMode mode) {
  switch (mode) {
    case ViewMode::Preview: return "preview";
    case ViewMode::Reference: return "reference";
    case ViewMode::Split: return "split";
    case ViewMode::Difference: return "difference";
    case ViewMode::SsbcResidual: return "ssbc-residual";
    case ViewMode::VplOverlay: return "vpls";
    case ViewMode::CutSize: return "cut-size";
  }
  return "?";
}

}  // namespace vplab::ui
