#pragma once
// The stability suite (docs/theory.md §9, §10):
//   1 flicker: a scripted small motion of the light, and separately of the camera, over F frames; per method the mean
//     |I_t - I_{t-1}| against the same measure of path-traced frames, for coherent QMC VPLs (one seed: a small light
//     move moves every VPL a little) and for VPLs reshuffled every frame (a new seed per frame);
//   2 failure maps: where each method errs most (clamp: corners; plain VPLs: glossy surfaces and creases; SSBC:
//     borders and occlusions; shadow maps: leaks and acne), as heatmaps with their numbers;
//   3 extremes: a grid of parameter extremes, each checked for non-finite and negative pixels and timed.

#include <functional>
#include <string>
#include <vector>

#include "evaluation/harness.h"
#include "renderer/scene/scene.h"
#include "renderer/settings.h"

namespace vplab {

/// A copy of the scene with every light moved by `offset`: emissive triangles (their vertices duplicated, so geometry
/// sharing a vertex with a light stays where it is) and punctual lights. The copy is finalized.
Scene translateLights(const Scene& scene, const glm::vec3& offset);

/// Every flicker method's name: vpl, clamp, vsl and the generation variants (reject, bidirectional, metropolis) on
/// the CPU; vpl-gl and ssbc-gl in the GL preview.
const std::vector<std::string>& flickerMethodNames();

struct StabilityConfig {
  std::string outDir = "stability-out";
  int width = 96;
  int height = 96;
  int frames = 8;             ///< frames of each scripted motion (>= 2)
  bool quick = false;         ///< fewer methods and VPLs
  int vplCount = 256;         ///< N of every method unless an extreme sets it
  int cpuSpp = 2;             ///< samples per pixel of the CPU VPL renders
  int referenceSpp = 256;     ///< samples per pixel of the reference frames
  float lightStep = 0.004f;   ///< light translation per frame, as a fraction of the scene diagonal
  float cameraStep = 0.004f;  ///< camera translation per frame (sideways), as a fraction of the scene diagonal
  bool gl = true;
  GlBackend glBackend = GlBackend::Auto;
  uint32_t seed = 1;
  int threads = 0;
  bool writeImages = true;
  /// Flicker methods by name (flickerMethodNames()); empty = the default set (all of them).
  std::vector<std::string> flickerMethods;
  /// How the scene file is loaded (harness.h); empty: as it is.
  SceneLoader loadScene;
  std::function<void(const std::string&)> log;
};

/// One method under one motion. Flicker values are mean |I_t - I_{t-1}| over pixels, channels and frames 1..F-1.
struct FlickerRow {
  std::string motion;             ///< "light" or "camera"
  std::string method;             ///< e.g. "vpl", "clamp", "vpl-gl"
  std::string vplMode;            ///< "coherent" (one seed) or "reshuffled" (a new seed per frame)
  double flicker = 0.0;           ///< the method's frame-to-frame change
  double referenceFlicker = 0.0;  ///< the path-traced frames' own change (the true change plus their noise)
  double excess = 0.0;            ///< mean |(I_t - I_{t-1}) - (R_t - R_{t-1})|: change that is not in the scene
  double meanReference = 0.0;     ///< mean radiance of the reference frames, to read the others relatively
  std::vector<double> perFrame;   ///< mean |I_t - I_{t-1}| for t = 1..F-1
};

/// Runs `motion` ("light" or "camera") for every configured flicker method in both VPL modes. Compared quantity: the
/// indirect component. gl may be null (GL methods are then skipped).
std::vector<FlickerRow> measureFlicker(const Scene& scene, const StabilityConfig& config, const std::string& motion,
                                       PreviewBench* gl);

/// Where one method errs most.
struct FailureRow {
  std::string method;    ///< what is mapped, e.g. "clamp (cpu)" or "shadow maps 16 (gl vs cpu)"
  std::string against;   ///< "reference" or "cpu exact VPL (same VPLs)"
  std::string expected;  ///< where the course notes say this method fails
  double relMse = 0.0;
  double energyRatio = 1.0;
  double worstShare = 0.0;             ///< share of the summed error held by the worst 5% of pixels
  int worstTileX = 0, worstTileY = 0;  ///< top-left pixel of the 8x8 tile with the largest mean error
  double worstTileError = 0.0;         ///< its mean relative error
  std::string heatmap;                 ///< PNG written (relative to outDir), empty when images are off
  std::string image;                   ///< the method's image (PNG, relative to outDir)
};

std::vector<FailureRow> failureMaps(const OfflineScene& setup, const StabilityConfig& config, PreviewBench* gl);

/// One point of the extremes grid.
struct ExtremeRow {
  std::string parameter;  ///< "N", "b", "r", "epsilon", "k", "shadow map", "ssbc"
  std::string value;
  std::string method;  ///< "vpl", "vpl-kk", "vsl", "reject", "ssbc"
  Backend backend = Backend::Cpu;
  double timeMs = 0.0;  ///< generation + render
  BadPixels bad;
  double meanRadiance = 0.0;  ///< mean of the image (all components), for a sanity read
};

/// Every extreme on the CPU and (when gl is usable) in the preview, full images (Components::All).
std::vector<ExtremeRow> runExtremes(const OfflineScene& setup, const StabilityConfig& config, PreviewBench* gl);

struct StabilityOutcome {
  std::vector<FlickerRow> flicker;
  std::vector<FailureRow> failures;
  std::vector<ExtremeRow> extremes;
  bool extremesClean = true;  ///< no extreme produced a non-finite or negative pixel
  std::string reportPath;
  std::string glNote;  ///< why GL parts are missing, empty when they ran
};

/// The whole suite on one scene: flicker.csv, failures.csv, extremes.csv, heatmaps, charts and stability.md under
/// config.outDir.
StabilityOutcome runStability(const std::string& scenePath, const StabilityConfig& config);

}  // namespace vplab
