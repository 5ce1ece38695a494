// HeapWarmer (renderer/gl/heap_warmer.h): the heap it warms is where the next texture-sized allocations of the same
// thread land, and their pages are present before anything writes them. That is a property of glibc's allocator: the
// check is built only where glibc serves malloc (not under AddressSanitizer, whose allocator is its own), rather than
// skipped and counted as passed there.

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <vector>

#include "renderer/gl/heap_warmer.h"

#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
#include <sys/mman.h>
#include <unistd.h>
#define VPLAB_HEAP_WARMER_CHECKED 1
#endif

namespace vplab {
namespace {

#if defined(VPLAB_HEAP_WARMER_CHECKED)
/// The share of the pages of [p, p + bytes) resident in memory.
double residentShare(void* p, std::size_t bytes) {
  const std::size_t page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  auto begin = reinterpret_cast<std::uintptr_t>(p);
  begin = (begin + page - 1) / page * page;
  const std::uintptr_t end = (reinterpret_cast<std::uintptr_t>(p) + bytes) / page * page;
  std::vector<unsigned char> resident((end - begin) / page);
  if (mincore(reinterpret_cast<void*>(begin), end - begin, resident.data()) != 0) return -1.0;
  std::size_t count = 0;
  for (unsigned char r : resident) count += r & 1;
  return static_cast<double>(count) / static_cast<double>(resident.size());
}

TEST(HeapWarmer, LaterAllocationsLandInPresentPages) {
  constexpr std::size_t kWarmed = 64u << 20;
  HeapWarmer warmer(kWarmed);
  warmer.wait();
  EXPECT_EQ(warmer.bytes(), kWarmed);
  // Textures of a 640x480 preview: 4.9 MB (RGBA32F) and 1.2 MB (R32F); nothing has written them yet.
  std::vector<void*> textures;
  for (std::size_t bytes : {4915200u, 4915200u, 1228800u, 6556160u}) {
    void* p = std::malloc(bytes);
    ASSERT_NE(p, nullptr);
    EXPECT_GE(residentShare(p, bytes), 0.99) << bytes << " bytes";
    textures.push_back(p);
  }
  for (void* p : textures) std::free(p);
}
#endif

TEST(HeapWarmer, NothingBelowABlockAndStopsWhenDestroyedEarly) {
  HeapWarmer none(HeapWarmer::kBlockBytes - 1);
  none.wait();
  EXPECT_EQ(none.bytes(), 0u);
  // Destroyed at once: the blocks not yet touched are freed untouched, and the destructor returns.
  HeapWarmer early(std::size_t{256} << 20);
}

}  // namespace
}  // namespace vplab
