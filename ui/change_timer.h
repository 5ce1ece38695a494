#pragma once
// What the last change cost the preview, end to end. The editor splits the preview's work across frames
// (PreviewRenderer::render's budget), so one frame's time says little: a change costs from the moment it made the
// image stale until the image converged (every stale pass done), over however many frames that took. Pure logic,
// fed with the editor's clock and the renderer's timings.

#include "renderer/gl/preview_renderer.h"

namespace vplab::ui {

/// The editor's clock: seconds on the steady clock (what ChangeTimer is fed with).
double steadySeconds();

class ChangeTimer {
 public:
  /// A change made the preview stale at `seconds`. One that arrives before the previous change converged extends it:
  /// the time then runs from the first change the image has not caught up with.
  void changed(double seconds);
  /// VPL generation for the current change took `ms` (CPU).
  void vplsGenerated(double ms);
  /// One budgeted render call ended at `seconds`; its pass times are added to the change's. A complete image is the
  /// change's first image too, when no coarse one came before it.
  void rendered(double seconds, const PreviewTimings& timings);
  /// A coarse image of the change's new state was shown at `seconds` (CoarsePreview), before the final one.
  void coarseShown(double seconds);

  bool pending() const { return pending_; }
  /// Milliseconds since the pending change (0 when none is pending).
  double pendingMs(double seconds) const { return pending_ ? 1e3 * (seconds - start_) : 0.0; }
  /// The last converged change: wall milliseconds from the change to the final image (negative before the first),
  /// the render calls (frames) it took, its GPU time per pass summed over them (0: the pass was cached, not re-run)
  /// and the CPU time of its VPL generation (0: the VPLs were kept).
  double lastMs() const { return lastMs_; }
  int lastFrames() const { return lastFrames_; }
  const PreviewTimings& lastPasses() const { return lastPasses_; }
  double lastVplGenerationMs() const { return lastVplMs_; }
  /// The last converged change: wall milliseconds from the change to its first image, coarse or final.
  double lastFirstImageMs() const { return lastFirstMs_; }
  /// Whether the last converged change showed a coarse image first.
  bool lastHadCoarseImage() const { return lastCoarse_; }

 private:
  bool pending_ = false;
  double start_ = 0.0;
  int frames_ = 0;
  PreviewTimings passes_;
  double vplMs_ = 0.0;
  double firstMs_ = -1.0;  ///< of the pending change; < 0 until its first image
  double lastMs_ = -1.0, lastFirstMs_ = -1.0;
  bool lastCoarse_ = false;
  int lastFrames_ = 0;
  PreviewTimings lastPasses_;
  double lastVplMs_ = 0.0;
};

}  // namespace vplab::ui
