#pragma once
// Identities of data a renderer uploads (Scene::id, VplSet::id): with an object's address they tell a renderer that a
// new object took the place of the one it uploaded.

#include <atomic>
#include <cstdint>

namespace vplab {

/// A new value at every call, from one counter for the whole program (never 0).
inline std::uint64_t newObjectId() {
  static std::atomic<std::uint64_t> next{1};
  return next.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace vplab
