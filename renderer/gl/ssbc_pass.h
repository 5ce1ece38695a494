#pragma once
// Pass 5 of the preview: screen-space bias compensation (Novak et al. 2011; docs/theory.md §6, common/ssbc.glsl).
// R1 = T_r(I0) adds back what the bound b removed, as an image filter over the pixels within 1/sqrt(b); a second step
// R2 = T_r(R1) adds the next bounce of it. Hierarchical rings over mip levels of the G-buffer and of the step's input;
// with Settings::ssbcCoarseRings the coarse rings are evaluated on a 4x coarser grid and interpolated where the
// samples lie on the pixel's surface (elsewhere evaluated, in R2 extrapolated) and the fine rings only where the
// pixels' blocks are not flat.

#include <memory>
#include <vector>

#include "renderer/gl/resources.h"
#include "renderer/gl/screen_pass.h"
#include "renderer/scene/scene.h"
#include "renderer/settings.h"

namespace vplab {

/// What a compensation step reads and writes. The G-buffer must be bound at its units. What depends on it alone (the
/// tap factors at every mip level, the flat blocks) is made here when `gbufferDerivedCurrent` is false, and kept until
/// the G-buffer is drawn again.
struct SsbcImages {
  GlTexture& gPosition;
  GlTexture& gNormal;
  bool& gbufferDerivedCurrent;
  Target& i0;  ///< direct + indirect light, the first step's input
  Target& r1;  ///< T_r(I0), and the second step's input
  Target& r2;  ///< T_r(R1)
};

/// Whether the settings compensate at all: some steps, and a finite bound b > 0.
bool ssbcCompensates(const Settings& settings);

/// Where each mip level of a width x height image starts in the compensation's tap buffers (common/ssbc_levels.glsl):
/// the levels packed one after another, the total after the last, which must fit a buffer texture
/// (GlLimits::maxTextureBufferSize, checked by previewFitProblem before any rendering; llvmpipe's 2^27 texels are an
/// image of about 10000^2).
std::vector<int> ssbcTapLevelBases(int width, int height);

class SsbcPass {
 public:
  SsbcPass();
  ~SsbcPass();
  /// Runs min(ssbcSteps, 2) steps when the bound is finite (else none) and returns how many: R1 and R2 hold the
  /// residuals of those steps once `slices` has run them all. Each full-screen draw is a step of `slices`, in bands
  /// under a budget; a draw that reads its input's neighbours or mips follows the steps that complete them.
  int run(bool lambertOnly, const Camera& camera, const Settings& settings, const SsbcImages& images,
          const GlVertexArray& vao, PassSlices& slices);

 private:
  struct Targets;
  std::unique_ptr<Targets> targets_;
  BrdfVariants ssbc_;
  // The tap factors and I dA at level 0, and at the levels above it (SSBC_AVERAGE_FINER).
  DeferredProgram taps_, coarserTaps_, radiance_, coarserRadiance_;
  // Multi-resolution rings (Settings::ssbcCoarseRings, common/ssbc.glsl SSBC_SPLIT): the pass that interpolates the
  // coarse rings, the pass that evaluates them on the coarse grid, the pass that evaluates them where they cannot be
  // interpolated (SSBC_FALLBACK_PASS; in the second step SSBC_UPSAMPLE_PASS extrapolates them there instead) and the
  // pass that adds the fine rings where they are not zero (SSBC_FINE_PASS, with the flat-block mask of flatRows_ and
  // flatColumns_).
  BrdfVariants split_, coarse_, fine_;
  DeferredProgram flatRows_, flatColumns_;
  DeferredProgram fineMask_, fallbackMask_;  // where the fine and the fallback passes run (ssbc_mask.frag.glsl)
  BrdfVariants fallback_, upsample_;
  // What the run under way redoes of what depends on the G-buffer alone: taken when it starts, since its own steps
  // make these current.
  bool redoFlat_ = false, redoTaps_ = false;
};

}  // namespace vplab
