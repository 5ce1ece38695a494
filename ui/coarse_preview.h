#pragma once
// The first image of a slow change: the preview of the new state at half the width and height, shown upsampled while
// the full-size update goes on over the following frames (docs/editor.md "The first image of a change"). It is a
// complete image of the new settings, camera and VPLs, never a mix with the old state, and it is replaced by the
// full-size image when that is complete.
//
// Why a second renderer and not a coarser stage of the first: every pass of the preview, the VPL maps and the
// media's marches included, costs about its pixel count or its map size, and a renderer of its own keeps both its
// maps and its screen results across changes with the same invalidation rules (a camera move keeps its maps, b keeps
// its direct light), so the coarse image costs about a quarter of the full one's, whatever the change was.

#include <memory>

#include "renderer/gl/preview_renderer.h"
#include "renderer/image/image.h"

namespace vplab::ui {

class CoarsePreview {
 public:
  CoarsePreview();
  ~CoarsePreview();
  /// The settings of the coarse image of `full`: half its width and height (rounded up) and shadow maps half as wide,
  /// everything else as in `full` (the indirect light on a grid s times coarser than the coarse image, a quarter of
  /// full's gather and media work).
  static Settings coarseSettings(const Settings& full);

  /// Renders the new state completely (needs a current GL context) and returns it resampled to full's size.
  Image render(const Scene& scene, const VplSet& vpls, const Settings& full, const Camera& camera);
  /// One of PreviewRenderer's invalidate functions: what the editor tells the full-size renderer, it tells this one.
  void invalidate(void (PreviewRenderer::*what)());
  /// Wall milliseconds of the last render().
  double lastMs() const { return lastMs_; }

 private:
  std::unique_ptr<PreviewRenderer> renderer_;  ///< made by the first render()
  double lastMs_ = 0.0;
};

}  // namespace vplab::ui
