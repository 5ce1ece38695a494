#pragma once
// The interactive instant-radiosity preview (docs/theory.md §1, §4, §6-§8), rasterised with OpenGL 4.5:
//   1 G-buffer  2 direct light (shadow-mapped area samples + punctual lights)  3 VPL visibility maps (cube or ISM)
//   4 VPL gather (G_b, VSL, interleaved k x k) + geometry-aware de-interleave  5 screen-space bias compensation.
// The image is Le (seen directly) + direct + indirect (+ compensation), in the CPU renderer's linear units. In a scene
// with participating media the surfaces' light is attenuated along every light, VPL and camera segment, and the media
// add the light they scatter into camera rays (media_pass.h). Callers read the linear image back and tonemap it
// themselves (the editor's view, image files): exposure is not the renderer's.
// Needs a current GL context (HeadlessGlContext or the editor's window); does not create one.
//
// Each pass is a class of its own (direct_pass.h, gather_pass.h, ssbc_pass.h; the VPL maps behind vpl_visibility.h);
// this class owns the screen targets and decides which passes run.
//
// Invalidation: only the work a change affects is redone. Which passes the settings and the camera make stale is what
// renderer/invalidation.h says (staleAfterSettingsChange, staleAfterCameraMove), the same rules the editor follows;
// what the renderer is handed besides (a new scene, edited lights, a new or edited VPL set) adds the stages that
// depend on it. A VPL shadow map depends only on its caster and the map sizes, so a new VplSet (or invalidateVpls())
// whose positions are unchanged keeps the maps.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>

#include "renderer/gl/direct_pass.h"
#include "renderer/gl/gather_pass.h"
#include "renderer/gl/gl_limits.h"
#include "renderer/gl/gl_scene.h"
#include "renderer/gl/media_pass.h"
#include "renderer/gl/resources.h"
#include "renderer/gl/screen_pass.h"
#include "renderer/gl/shader.h"
#include "renderer/gl/ssbc_pass.h"
#include "renderer/gl/vpl_visibility.h"
#include "renderer/scene/scene.h"
#include "renderer/settings.h"
#include "renderer/vpl/vpl.h"

namespace vplab {

/// The grid the indirect light is gathered on for a width x height image at Settings::indirectDownscale s: one pixel
/// per s x s block, the last ones partial.
inline glm::ivec2 indirectGridSize(int width, int height, int downscale) {
  return {(width + downscale - 1) / downscale, (height + downscale - 1) / downscale};
}

/// GPU time per pass in milliseconds (GL_TIME_ELAPSED); 0 for a pass that was skipped because nothing it depends on
/// changed. The lights' and the VPLs' maps are drawn on the CPU and uploaded: their time is their wall time.
struct PreviewTimings {
  double gbufferMs = 0, directShadowMs = 0, directMs = 0, vplShadowMs = 0, gatherMs = 0, ssbcMs = 0;
  /// The media's scattering along camera rays with its merge (media_pass.h; 0 in a scene without media).
  double mediaMs = 0;
  double totalMs() const {
    return gbufferMs + directShadowMs + directMs + vplShadowMs + gatherMs + mediaMs + ssbcMs;
  }
  /// CPU wall time per pass in milliseconds, from issuing its commands until the GPU finished them (the timer
  /// query result is waited for), so it includes driver overhead that GL_TIME_ELAPSED does not see.
  double gbufferWallMs = 0, directShadowWallMs = 0, directWallMs = 0, vplShadowWallMs = 0, gatherWallMs = 0,
         ssbcWallMs = 0, mediaWallMs = 0;
  /// CPU wall time of the whole render() call (uploads and invalidation checks included).
  double frameWallMs = 0;
  /// Pixel x VPL evaluations the gather pass performed (each with one shadow-map fetch): pixels of the indirect
  /// light's grid (Settings::indirectDownscale) x N / k^2.
  double gatherEvaluations = 0;
  /// GPU time of the geometry-aware de-interleave, already counted in gatherMs (in directMs when only that ran).
  double deinterleaveMs = 0;
  /// False when the call's budget ran out before every stale pass ran: the image is not the final one yet.
  bool complete = true;
  /// Share of the passes of the current change that have run, [0, 1].
  float progress = 1.0f;
};

/// How often each pass ran since construction (tests check the invalidation rules with these).
struct PreviewCounters {
  int gbuffer = 0, directShadowMaps = 0, direct = 0, vplShadowMaps = 0, gather = 0, ssbc = 0, media = 0;
};

/// Which image readLinear() returns.
enum class PreviewOutput {
  Final,     ///< Le + direct + indirect + compensation (through media: attenuated, plus their scattered light and its
             ///< approximate compensation, media_pass.h)
  Direct,    ///< direct light (reflected) only; through media attenuated, plus the lights' single scattering
  Indirect,  ///< de-interleaved VPL gather only; through media attenuated, plus the VPLs' in-scattering
  Residual,  ///< screen-space compensation R1 + R2 only
  Scattered,  ///< the light the media scatter into camera rays only (0 without media): the lights' and the VPLs', and
              ///< with compensation on (ssbcSteps > 0) its approximate compensation
};

/// Whether the preview of `scene` with `vplCount` VPLs under `settings` fits the context's limits: an empty string, or
/// one sentence naming the limit exceeded (texture size, array layers, memory) and the options that lower the need.
/// render() checks it before any GL work and throws it; commands call it before generating VPLs.
std::string previewFitProblem(const Scene& scene, std::size_t vplCount, const Settings& settings,
                              const GlLimits& limits);

/// About the bytes of textures the preview's first frame creates under `settings`, from the settings alone (vplab
/// preview warms that much heap before the scene is read, heap_warmer.h): its screen targets and its VPLs' shadow maps
/// as hemicubes. The lights' maps, which depend on the scene, are left out.
std::size_t previewFirstFrameBytes(const Settings& settings);

/// The pixels one set of the preview's screen passes runs on (preview_renderer.cpp).
struct ScreenGrid;

class PreviewRenderer {
 public:
  PreviewRenderer();
  ~PreviewRenderer();
  PreviewRenderer(const PreviewRenderer&) = delete;
  PreviewRenderer& operator=(const PreviewRenderer&) = delete;

  /// Renders settings.width x settings.height. The scene is compared by address and Scene::id, the VPL set by address
  /// and VplSet::id: call invalidateScene() / invalidateVpls() after editing them in place.
  /// budgetMs splits long work across calls (the editor's frames): passes run in order until one finishes after the
  /// budget is spent; the next call resumes with the remaining ones (and redoes any that a new change made stale).
  /// The G-buffer (in bands of rows), the lights' maps (a cube face at a time), the VPL maps (for a technique that
  /// slices them, ISM), the direct light and the gather (a draw per interleaving subset and range of lights, at most 64
  /// VPLs per pixel), the media, the merge and the compensation with the compositions after it are split too, so that
  /// a call overruns the budget by at most one slice, not one pass: a full-screen draw is drawn in bands of rows sized
  /// to take about PassSlices::kSliceMs each (screen_pass.h), and a draw that reads its inputs' neighbours starts only
  /// once every band of them is drawn. The image is final when the result's `complete` is set; it is then the same as
  /// one unbudgeted call gives.
  PreviewTimings render(const Scene& scene, const VplSet& vpls, const Settings& settings, const Camera& camera,
                        double budgetMs = std::numeric_limits<double>::infinity());

  void invalidateScene();
  /// The scene's punctual lights were edited in place (no triangle moved): the lights' shadow maps and the direct light
  /// are redone, the geometry and the VPL maps are kept.
  void invalidateLights();
  /// The VPL set was edited in place: its data is re-uploaded; shadow maps are re-rendered only if a position changed.
  void invalidateVpls();
  /// Forgets the cached screen-space results (G-buffer to compensation) so that the next render redoes them, as a camera
  /// move would; shadow maps are kept. For timing steady-state frames.
  void invalidateFrame();

  /// Linear radiance (before tonemapping) of the last render, row 0 at the top. Direct and Indirect are de-interleaved
  /// from the last render's interleaved results when asked for (a frame merges only their sum).
  Image readLinear(PreviewOutput which = PreviewOutput::Final);
  /// The VPL visibility technique of the last render: Settings::visibility, `auto` resolved (resolveVisibility).
  VisibilityMethod visibilityInUse() const { return visibilityMethod_; }
  /// Where the last render keeps each of the scene's density grids (MediaPass::gridSummary); empty without one.
  std::vector<std::string> densityGridsInUse() const { return media_.gridSummary(); }

  const PreviewCounters& counters() const { return counters_; }

 private:
  struct Targets;
  void ensureTargets(int width, int height);
  /// The geometry-aware de-interleave of weights.x x direct + weights.y x indirect on `grid` into `out`, as steps of
  /// `slices`.
  void mergeInterleaved(ScreenGrid& grid, glm::vec2 weights, GlFramebuffer& out, PassSlices& slices);
  /// Draws into `out` the full-resolution image of the indirect light's grid (preview/upsample.frag.glsl) with the
  /// terms `terms` selects: x emission and direct light, y the gather, z R1, w R2; as steps of `slices`.
  void upsample(glm::vec4 terms, GlFramebuffer& out, PassSlices& slices);
  /// Creates the visibility technique and compiles the gather (and the media's VPL pass) for it and for the scene's
  /// media when Settings::visibility or whether the scene has media changed.
  void useVisibility(VisibilityMethod method, const MediaShaderLayout& media);
  /// Through the scene's media (none: nothing to do): target = weights.x T(camera, surface) target + weights.y the
  /// lights' single scattering + weights.z the VPLs' in-scattering + weights.w their approximate compensation, for the
  /// last frame (MediaPass::compose).
  void throughMedia(Target& target, glm::vec4 weights);
  /// What the media passes need of this frame's camera and scene.
  MediaPass::Frame mediaFrame(const Camera& camera, const Settings& settings) const;

  std::unique_ptr<Targets> targets_;
  std::unique_ptr<GlScene> glScene_;
  const Scene* scene_ = nullptr;
  std::uint64_t sceneId_ = 0;
  const VplSet* vplSet_ = nullptr;
  std::uint64_t vplSetId_ = 0;
  bool vplsDirty_ = true;
  bool sceneDirty_ = true;
  bool lightsDirty_ = false;
  /// False until the lights' maps exist for the current scene.
  bool shadowsValid_ = false;
  /// True when every material of the scene is Lambert (the passes' BRDF_LAMBERT_ONLY variants).
  bool lambertOnly_ = false;

  // The G-buffer of a scene with textures, and of one without (SCENE_TEXTURED 0, preview/gbuffer.frag.glsl).
  DeferredProgram gbufferTextured_, gbufferUntextured_;
  ShaderProgram gbufferBackground_;
  DirectLightPass direct_;
  /// The VPL visibility technique of Settings::visibility.
  std::unique_ptr<VplVisibility> vplVisibility_;
  VisibilityMethod visibilityMethod_ = VisibilityMethod::Cube;
  /// The media the gather was compiled for.
  MediaShaderLayout gatherMedia_;
  MediaPass media_;
  /// The media media_ holds, to notice an edit in place.
  std::vector<Medium> uploadedMedia_;
  VplGatherPass gather_;
  /// The de-interleave (preview/deinterleave.frag.glsl): its row pass merging both components, or one alone (the
  /// direct light at full resolution and the gather on the grid when s > 1, a component read back), and its columns.
  DeferredProgram deinterleaveRows_, deinterleaveRowsOneInput_;
  ShaderProgram deinterleaveColumns_;
  SsbcPass ssbc_;
  /// The indirect light's grid at 1/s resolution: its G-buffer and its I0 (preview/indirect_grid.frag.glsl).
  DeferredProgram gridGbuffer_, gridInput_;
  /// The two passes of the upsample from the grid (preview/upsample.frag.glsl).
  DeferredProgram compose_, gridLight_, upsample_;
  // Compensation steps of the last frame whose results R1, R2 are current (0: none, the residual is 0).
  int residualSteps_ = 0;
  GlVertexArray vao_;
  GlTimerQuery timer_;

  // What the cached results were computed with.
  bool haveFrame_ = false;
  Camera lastCamera_;
  Settings lastSettings_;

  PreviewCounters counters_;
  /// Queried at the first render, before the renderer allocates anything, so its own maps do not count against it.
  GlLimits limits_;

  /// Passes that are stale and have not run yet (render() with a budget can leave some for the next call).
  struct PendingPasses {
    // mediaLights, mediaVpls: the media's scattering of the lights and of the VPLs (media_pass.h).
    bool gbuffer = false, directMaps = false, vplMaps = false, direct = false, gather = false, mediaLights = false,
         mediaVpls = false, merge = false, ssbc = false;
    bool media() const { return mediaLights || mediaVpls; }
    int count() const {
      return gbuffer + directMaps + vplMaps + direct + gather + media() + merge + ssbc;
    }
    bool any() const { return count() > 0; }
  };
  PendingPasses pending_;
  /// Where the G-buffer, the merge and the compensation (with the compositions after it) cut short by a budget go on;
  /// the direct light, the gather and the media keep their own.
  PassSlices gbufferSlices_, mergeSlices_, ssbcSlices_;
  /// Whether the merge under way merges the direct light again (taken when it starts).
  bool mergeDirect_ = false;
  int jobDone_ = 0, jobTotal_ = 0;
};

}  // namespace vplab
