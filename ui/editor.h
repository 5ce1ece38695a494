#pragma once
// `vplab edit`: the interactive editor. A GLFW window with Dear ImGui panels around one view of the GL preview,
// the offline result, their split or difference, the SSBC residual or the VPLs. The editor owns the scene, the
// Settings, the VplSet and the renderers; panels edit them and the editor re-runs exactly the stale work
// (renderer/invalidation.h). With a script (ui/script.h) it runs unattended and exits: tests and benchmarks.

#include "renderer/settings.h"

#include <string>

namespace vplab::ui {

struct EditorOptions {
  std::string scenePath;       ///< glTF file opened at start
  std::string scriptPath;      ///< empty: interactive
  std::string screenshotPath;  ///< written (PNG, whole window) after the script, then the editor exits
  /// Initial settings (CLI options and --settings applied). Where they say nothing, those of `vplab preview`
  /// (previewDefaultSettings): interleaved over 4 x 4 subsets, the indirect light on the half-resolution grid, VPL
  /// maps of 64^2 texels per face. At the fitted size they make an edit show in about a tenth of a second on llvmpipe,
  /// where k = s = 1 takes 0.2-0.8 s on the Cornell boxes and seconds in the smoke (docs/benchmarks.md, "Editing in
  /// the editor"). The settings panel, a settings file or --interleave 1 --indirect-downscale 1 give the full gather.
  Settings settings = previewDefaultSettings();
  /// The preview's size follows the view area (times the resolution scale) instead of settings.width x height;
  /// an explicit image size (--size, the offline panel's image size, a script's `set width`) turns it off.
  bool fitPreview = true;
  /// Preview pixels per view-area pixel along each axis while fitted, [0.05, 1]. A change costs about in proportion
  /// to the pixels (docs/editor.md, "Preview size"): 0.4 gives the 1280x720 window's view about the 65k pixels of the
  /// fixed 256x256 preview it replaces, so the editor stays as responsive as it was on two cores with llvmpipe.
  float previewScale = 0.4f;
  int windowWidth = 1280;
  int windowHeight = 720;
};

/// Opens the window and runs until it is closed or the script ends. Returns the process exit status: 0, or 1 when
/// a script expectation failed. Throws std::runtime_error when no window can be opened (no display) and SceneError
/// when the initial scene cannot be loaded.
int runEditor(const EditorOptions& options);

}  // namespace vplab::ui
