#pragma once
// Touching the heap ahead of llvmpipe (docs/benchmarks.md "Warming the heap for the first frame"). llvmpipe zero-fills
// every texture it creates, on the thread that makes the GL call. On a virtual machine whose freed memory goes back to
// the hypervisor, the first touch of each page then costs 2-3 us on that thread: the Cornell box's first frame at
// 640x480 created 120 MB of textures, about 30k such faults, 80 ms of a 350 ms process.
//
// A HeapWarmer, made on the thread that will create the textures, takes that many bytes from that thread's heap in
// blocks, touches them on a thread of its own at idle priority (the second core idles while the context starts and
// the first passes run on the main thread), and frees each block once touched. The textures created after that are
// placed in those blocks, whose pages are already present. Where there is no glibc it does nothing.

#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace vplab {

class HeapWarmer {
 public:
  /// Starts warming about `bytes` (at most 1 GiB) of the calling thread's heap.
  explicit HeapWarmer(std::size_t bytes);
  /// Frees the blocks not yet touched and joins.
  ~HeapWarmer();
  HeapWarmer(const HeapWarmer&) = delete;
  HeapWarmer& operator=(const HeapWarmer&) = delete;

  /// Waits until every block is touched and freed (tests).
  void wait();
  /// The bytes taken from the heap.
  std::size_t bytes() const { return blocks_.size() * kBlockBytes; }

  /// Texture-sized blocks: below glibc's largest threshold for serving an allocation from a mapping of its own (32 MiB),
  /// so that they are heap and the textures placed in them are too.
  static constexpr std::size_t kBlockBytes = std::size_t{8} << 20;

 private:
  std::vector<void*> blocks_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace vplab
