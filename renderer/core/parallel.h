#pragma once
// The render machinery every CPU pass shares: a thread pool over tiles, cancellation and progress.
// Results must not depend on the thread count: work items derive their random streams from their own index.

#include <atomic>
#include <cstdint>
#include <functional>

namespace vplab {

/// Progress and cancellation shared between a pass and whoever started it (CLI, editor thread, test).
struct RenderControl {
  /// Set to true from any thread to stop the pass at the next work item; the pass then returns what it has.
  std::atomic<bool> cancel{false};
  /// Called with a fraction in [0, 1] from worker threads, at most every few milliseconds. May be empty.
  std::function<void(float)> onProgress;

  bool cancelled() const { return cancel.load(std::memory_order_relaxed); }
};

/// Number of worker threads for a Settings::threads value (0 = all hardware threads).
int resolveThreadCount(int requested);

/// Runs body(index, threadIndex) for index in [0, count) on `threads` threads, handing out indices dynamically.
/// Sets flush-to-zero and denormals-are-zero on every worker (Embree asks for it). Stops handing out work once
/// control->cancelled(); reports progress as finished/count. Returns false when cancelled.
bool parallelFor(int64_t count, int threads, const std::function<void(int64_t index, int threadIndex)>& body,
                 RenderControl* control = nullptr);

}  // namespace vplab
