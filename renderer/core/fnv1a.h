#pragma once
// FNV-1a, 64 bits (Fowler, Noll and Vo): a short stable name for some bytes, the same in every run and on every
// machine, for file names and cache keys; not for anything an adversary chooses.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

namespace vplab {

class Fnv1a64 {
 public:
  void add(const void* data, std::size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) hash_ = (hash_ ^ p[i]) * 1099511628211ull;
  }
  void add(std::string_view text) { add(text.data(), text.size()); }
  /// The hash as 16 lower-case hex digits.
  std::string hex() const {
    char out[17];
    std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(hash_));
    return out;
  }

 private:
  std::uint64_t hash_ = 14695981039346656037ull;  // FNV's 64-bit offset basis
};

/// The 16 hex digits of `text`'s FNV-1a hash.
inline std::string fnv1a64Hex(std::string_view text) {
  Fnv1a64 h;
  h.add(text);
  return h.hex();
}

}  // namespace vplab
