#include "ui/change_timer.h"

#include <chrono>

namespace vplab::ui {

double steadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void ChangeTimer::changed(double seconds) {
  if (pending_) return;
  pending_ = true;
  start_ = seconds;
  frames_ = 0;
  passes_ = PreviewTimings{};
  vplMs_ = 0.0;
  firstMs_ = -1.0;
}

void ChangeTimer::vplsGenerated(double ms) {
  if (pending_) vplMs_ += ms;
}

void ChangeTimer::coarseShown(double seconds) {
  if (pending_ && firstMs_ < 0.0) firstMs_ = 1e3 * (seconds - start_);
}

void ChangeTimer::rendered(double seconds, const PreviewTimings& t) {
  if (!pending_) return;
  ++frames_;
  passes_.gbufferMs += t.gbufferMs;
  passes_.directShadowMs += t.directShadowMs;
  passes_.directMs += t.directMs;
  passes_.vplShadowMs += t.vplShadowMs;
  passes_.gatherMs += t.gatherMs;
  passes_.mediaMs += t.mediaMs;
  passes_.ssbcMs += t.ssbcMs;
  if (!t.complete) return;
  pending_ = false;
  lastMs_ = 1e3 * (seconds - start_);
  lastCoarse_ = firstMs_ >= 0.0;
  lastFirstMs_ = lastCoarse_ ? firstMs_ : lastMs_;
  lastFrames_ = frames_;
  lastPasses_ = passes_;
  lastVplMs_ = vplMs_;
}

}  // namespace vplab::ui
