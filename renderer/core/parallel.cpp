#include "renderer/core/parallel.h"

#include <xmmintrin.h>
#include <pmmintrin.h>

#include <algorithm>
#include <chrono>
#include <mutex>
#include <thread>
#include <vector>

namespace vplab {

int resolveThreadCount(int requested) {
  if (requested > 0) return requested;
  unsigned hw = std::thread::hardware_concurrency();
  return hw > 0 ? static_cast<int>(hw) : 1;
}

bool parallelFor(int64_t count, int threads, const std::function<void(int64_t, int)>& body, RenderControl* control) {
  if (count <= 0) return !(control && control->cancelled());
  threads = std::max(1, std::min<int>(resolveThreadCount(threads), static_cast<int>(std::min<int64_t>(count, 1024))));
  std::atomic<int64_t> next{0};
  std::atomic<int64_t> finished{0};
  std::mutex progressMutex;
  auto lastReport = std::chrono::steady_clock::now();

  auto worker = [&](int threadIndex) {
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
    for (;;) {
      if (control && control->cancelled()) return;
      int64_t i = next.fetch_add(1, std::memory_order_relaxed);
      if (i >= count) return;
      body(i, threadIndex);
      int64_t done = finished.fetch_add(1, std::memory_order_relaxed) + 1;
      if (control && control->onProgress) {
        auto now = std::chrono::steady_clock::now();
        std::unique_lock lock(progressMutex, std::try_to_lock);
        if (lock.owns_lock() && (now - lastReport > std::chrono::milliseconds(50) || done == count)) {
          lastReport = now;
          control->onProgress(static_cast<float>(done) / static_cast<float>(count));
        }
      }
    }
  };

  std::vector<std::thread> pool;
  pool.reserve(static_cast<std::size_t>(threads - 1));
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker, t);
  worker(0);
  for (std::thread& t : pool) t.join();
  return !(control && control->cancelled());
}

}  // namespace vplab
