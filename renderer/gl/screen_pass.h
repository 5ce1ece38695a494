#pragma once
// What the preview's screen passes share: a colour target with its framebuffer, the full-screen triangle, a pass
// compiled for any material and for Lambert-only scenes, and the block layout of interleaved sampling.

#include <functional>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "renderer/gl/resources.h"
#include "renderer/gl/shader.h"

namespace vplab {

/// A colour texture with its own framebuffer.
struct Target {
  GlTexture texture;
  GlFramebuffer framebuffer;
  Target(int w, int h);
};

/// Draws the full-screen triangle (preview/fullscreen.vert.glsl makes it from gl_VertexID) with `program`.
void drawFullscreen(ShaderProgram& program, const GlVertexArray& vao);

/// A screen pass in two variants: for any material, and with BRDF_LAMBERT_ONLY (common/brdf.glsl) for scenes whose
/// materials are all Lambert, where llvmpipe would otherwise run the GGX code under a lane mask. Each is compiled when
/// first asked for: a scene draws with one of them, and a program costs a cold start on llvmpipe a few milliseconds
/// even from Mesa's shader cache (a compile error is thrown then, as ShaderError).
class BrdfVariants {
 public:
  BrdfVariants(const std::string& fragmentShader, std::vector<std::string> defines = {});
  ShaderProgram& operator[](bool lambert) { return lambert ? lambertOnly_.get() : general_.get(); }

 private:
  DeferredProgram general_, lambertOnly_;
};

/// Interleaved sampling (common/interleaved.glsl): the width x height image is drawn as k x k blocks of
/// blockWidth x blockHeight texels, block (sx, sy) holding the pixels of subset sx + k sy.
struct InterleavedLayout {
  int width = 0, height = 0, k = 1, blockWidth = 0, blockHeight = 0;
};

/// The time of a banded draw as fixed + perRow x rows, fitted to its last two bands. A draw of a dense scene's triangles
/// pays llvmpipe's geometry stage (every vertex shaded, every triangle set up) again in each band whatever its rows, so
/// a model of time per row alone shrinks its bands to one row and multiplies that fixed cost by the image's height.
class BandCost {
 public:
  /// A band of `rows` rows took `ms`.
  void measured(int rows, double ms);
  /// The rows of the next band of a draw with `rowsLeft` rows left, to take about sliceMs: every row left when the
  /// fixed part alone takes half the slice (smaller bands would only repeat it); an eighth of `rows` before any
  /// measurement.
  int nextBand(int rowsLeft, int rows, double sliceMs) const;
  double fixedMs() const { return fixedMs_; }
  double msPerRow() const { return msPerRow_; }

 private:
  double fixedMs_ = 0.0, msPerRow_ = 0.0;
  int lastRows_ = 0;
  double lastMs_ = 0.0;
};

/// A pass's work as a fixed sequence of slices that a budgeted render (PreviewRenderer::render) can stop between and
/// resume at in its next call. Each call replays the pass's code between begin() and end(): the steps that ran in
/// earlier calls are skipped, and after each slice that runs, outOfTime() is asked whether to stop. So the code must
/// register the same steps in the same order on every call of one run (a condition that a step itself changes is
/// taken once, when the run starts: starting()), and state that later steps read (bound textures, uniforms, blending)
/// is set outside the steps. Without outOfTime every step runs whole: a draw split into bands gives the same texels
/// as one draw, since each fragment is computed alone and a pixel's blended draws keep their order.
class PassSlices {
 public:
  /// Starts a call; outOfTime empty: no budget, the remaining steps all run.
  void begin(std::function<bool()> outOfTime = {});
  /// Whether this call starts the run (no step has run yet).
  bool starting() const { return done_ == 0 && bandRow_ == 0; }
  /// One slice: runs `work` unless an earlier call ran it or this call has stopped.
  void step(const std::function<void()>& work);
  /// A draw into the rectangle (x, y, width, height) of the bound framebuffer, as one step. Under a budget it is drawn
  /// in bands of rows (glScissor), each a slice sized from this step's measured cost (BandCost) so that it takes
  /// about kSliceMs; a band's texels must depend only on what was complete before the draw began.
  void bands(glm::ivec4 rect, const std::function<void()>& draw);
  /// Ends the call: true when every step has run (the next call starts a new run), false when some are left.
  bool end();
  /// Forgets the steps done: what the pass reads changed, so its next run starts over.
  void restart();

  /// How long a slice should take: the most a budgeted call overruns its budget by, about.
  static constexpr double kSliceMs = 20.0;

 private:
  // Asks outOfTime after a slice; true when the call must stop.
  bool stopAfterSlice();

  std::function<bool()> outOfTime_;
  // Steps met in this call's replay, steps finished in the run, and rows of the banded step `done_` drawn already.
  int seen_ = 0, done_ = 0, bandRow_ = 0;
  bool stopped_ = false;
  // Per step: the cost of its bands, kept across runs.
  std::vector<BandCost> bandCosts_;
};

}  // namespace vplab
