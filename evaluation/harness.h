#pragma once
// What the sweeps (bench, stability) need around the two renderers: the exact CPU VPL render, the GL preview in a
// headless context, and cached references, all returning an image plus the time it took. Compared like with like:
// with Components::Indirect every backend returns indirect light only (CPU: renderVpl's indirect component; GL: the
// de-interleaved gather plus the screen-space residual), which is the part the many-light methods approximate; with
// Components::All the full image.

#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "renderer/gl/context.h"
#include "renderer/gl/preview_renderer.h"
#include "renderer/image/image.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/scene/scene.h"
#include "renderer/settings.h"
#include "renderer/vpl/vpl.h"

namespace vplab {

enum class Backend { Cpu, Gl };

/// Turns a scene file into the scene a sweep runs on. The CLI passes its own (app/scene_input.h: staged as --stage
/// says, the lights sidecar applied, warnings reported), so that bench and stability see a file exactly as every
/// other command does; empty means the file as it is (loadScene).
using SceneLoader = std::function<Scene(const std::string& path)>;
/// loader(path), or loadScene(path) when loader is empty.
Scene loadSweepScene(const SceneLoader& loader, const std::string& path);
const char* toString(Backend backend);

/// One measured render.
struct MeasuredImage {
  Image image;
  double generationMs = 0.0;  ///< VPL generation (pilot and rejection included); 0 for references
  double renderMs = 0.0;      ///< CPU: wall time of renderVpl on all threads. GL: GPU time of the frame's passes
  double totalMs() const { return generationMs + renderMs; }
  VplStats vplStats;
};

/// The sweeps' CPU renders of a scene ready for the CPU passes, each returning the image and the time it took.
/// renderVpl with `method` (Vpl, VplKK or Vsl) on the given VPLs, restricted to settings.components.
MeasuredImage renderCpu(const OfflineScene& offline, Method method, const VplSet& vpls, const Settings& settings);
/// A render at equal time: passes of fresh light paths (seed + pass, one pixel sample each, VPL generation included)
/// averaged until `seconds` have passed (at least one pass), so every method spends its time where its error is.
struct EqualTimeRender {
  Image image;
  int passes = 0;
  double seconds = 0.0;
  double clampEnergyRemoved = 0.0;  ///< mean over the passes
};
EqualTimeRender renderForSeconds(const OfflineScene& offline, Method method, const Settings& settings, double seconds);
/// renderReference at settings.samplesPerPixel, settings.components.
MeasuredImage renderReferenceImage(const OfflineScene& offline, const Settings& settings);

/// The GL preview in its own headless context (created on first use; never throws for a missing GL: available()
/// is false and error() says why).
class PreviewBench {
 public:
  explicit PreviewBench(GlBackend backend = GlBackend::Auto);
  ~PreviewBench();
  bool available();
  const std::string& error() const { return error_; }
  std::string description();

  /// Renders a whole frame from scratch (scene and VPLs invalidated, so shadow maps are re-rendered) and reads back
  /// the part named by settings.components (Direct is not offered by the comparison and is a programmer error).
  /// renderMs: wall time of the whole frame up to glFinish (the faster of two). With Components::Indirect the direct
  /// light (not compared) is rendered with one shadow-mapped sample (Settings::directLightSamples = 1) so that the time
  /// is the VPL work's.
  MeasuredImage render(const Scene& scene, const VplSet& vpls, const Settings& settings, const Camera& camera);

 private:
  bool tried_ = false;
  GlBackend backend_;
  std::string error_;
  std::unique_ptr<HeadlessGlContext> context_;
  std::unique_ptr<PreviewRenderer> renderer_;
  bool warmedUp_ = false;
};

/// The part of the preview's last frame named by settings.components, in linear radiance: All is the final image;
/// Indirect the de-interleaved gather plus the screen-space residual (with SSBC on and a finite clamp); Direct the
/// final image less those two (emission seen directly and the direct light).
Image readPreviewComponents(PreviewRenderer& renderer, const Settings& settings);

/// A reference for (scene, size, spp, components, seed), read from `cacheDir` when it was rendered before, else
/// rendered and stored there as EXR. The file name holds every key and a hash of the scene (geometry, materials,
/// lights, camera: staging or a lights sidecar changes it), so a different setting or scene never reuses a file.
/// cacheDir empty: no cache. `cached`, when given, says whether the file was reused.
MeasuredImage cachedReference(const OfflineScene& setup, const std::string& sceneName, const Settings& settings,
                              const std::string& cacheDir, bool* cached = nullptr);

/// "cornell-box" for ".../cornell-box.gltf".
std::string sceneStem(const std::string& path);

/// Display exposure (stops) that maps the image's mean luminance to 0.18, clamped to [-12, 12]; 0 for black.
float autoExposure(const Image& image);

/// Pixels with any NaN/Inf channel, and finite pixels with any channel < 0.
struct BadPixels {
  std::size_t nonFinite = 0;
  std::size_t negative = 0;
  std::size_t total() const { return nonFinite + negative; }
};
BadPixels countBadPixels(const Image& image);

}  // namespace vplab
