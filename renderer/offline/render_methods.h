#pragma once
// The offline render methods: the one list every user of "a way to render an image on the CPU" walks. The command
// line and settings spell a method by its name here (toString(Method) in renderer/settings.h); `vplab render`, the
// bench harness, the stability suite and the editor's offline pass call `render` from the row instead of naming the
// methods. Adding a method: a Method value, its render function (same signature as renderVpl), one row in
// renderMethods() (render_methods.cpp), and its bench rows in evaluation/sweep.cpp if it has parameters to sweep.

#include <functional>
#include <vector>

#include "renderer/core/parallel.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/offline/vpl_renderer.h"
#include "renderer/settings.h"
#include "renderer/vpl/vpl.h"

namespace vplab {

using OnPass = std::function<void(const Image& mean, int samplesSoFar)>;

struct RenderMethod {
  Method id;
  const char* label;     ///< for people: legends, reports, the editor
  const char* citation;  ///< the paper it follows
  const char* summary;   ///< one sentence: what it computes and where it fails
  bool usesVpls;         ///< lights with the VplSet it is handed (the caller generates it from the same settings)
  bool usesClampBound;   ///< the clamp bound b changes its image
  bool forMedia;         ///< differs from the plain VPL render only in scenes with participating media
  /// Renders settings.width x settings.height (samplesPerPixel samples: pass offlineRenderSettings()). Methods that
  /// do not use VPLs ignore `vpls`.
  VplRenderResult (*render)(const OfflineScene& offline, const VplSet& vpls, const Settings& settings,
                            RenderControl* control, OnPass onPass);
};

/// Every method, in the order Method lists them.
const std::vector<RenderMethod>& renderMethods();
const RenderMethod& renderMethod(Method id);
/// "vpl|vpl-kk|...": the names, for --help and error messages (the reference left out unless asked).
std::string renderMethodNames(bool withReference);

}  // namespace vplab
