#include "renderer/gl/heap_warmer.h"

#include <algorithm>
#include <climits>
#include <cstdlib>
#include <system_error>

#if defined(__GLIBC__)
#include <malloc.h>
#include <pthread.h>
#include <sched.h>
#endif

namespace vplab {

HeapWarmer::HeapWarmer(std::size_t bytes) {
#if defined(__GLIBC__)
  bytes = std::min(bytes, std::size_t{1} << 30);
  if (bytes < kBlockBytes) return;
  // Allocations up to 32 MiB from the heap, not from mappings of their own (which a free unmaps: fresh pages again),
  // and freed heap kept rather than handed back to the system.
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, static_cast<int>(std::min<std::size_t>(bytes + (std::size_t{64} << 20), INT_MAX)));
  // Taken here: a thread's allocations come from its own arena, and the textures' from the calling thread's.
  for (std::size_t taken = 0; taken < bytes; taken += kBlockBytes) {
    void* block = std::malloc(kBlockBytes);
    if (!block) break;  // only a speed-up: the textures fault in as before
    blocks_.push_back(block);
  }
  auto warm = [this] {
    // Idle priority: it only runs on a core nothing else wants (Linux: SCHED_IDLE for this thread alone).
    sched_param none{};
    pthread_setschedparam(pthread_self(), SCHED_IDLE, &none);
    for (void* block : blocks_) {
      // A write per page faults it in; volatile, since a store to memory about to be freed is otherwise dropped.
      if (!stop_.load(std::memory_order_relaxed))
        for (std::size_t at = 0; at < kBlockBytes; at += 4096) static_cast<volatile char*>(block)[at] = 0;
      std::free(block);
    }
  };
  try {
    thread_ = std::thread(warm);
  } catch (const std::system_error&) {
    // No thread to spare: nothing warmed, nothing lost.
    for (void* block : blocks_) std::free(block);
    blocks_.clear();
  }
#else
  (void)bytes;
#endif
}

void HeapWarmer::wait() {
  if (thread_.joinable()) thread_.join();
}

HeapWarmer::~HeapWarmer() {
  stop_.store(true, std::memory_order_relaxed);
  wait();
}

}  // namespace vplab
