#pragma once
// VPL sets compared member by member: memcmp would also compare the padding bytes between Vpl::inMedium and
// Vpl::medium, which hold whatever the stack held (they differed between thread counts under AddressSanitizer).

#include <vector>

#include "renderer/vpl/vpl.h"

namespace vplab::test {

inline bool sameVpl(const Vpl& a, const Vpl& b) {
  return a.position == b.position && a.normal == b.normal && a.geometricNormal == b.geometricNormal &&
         a.incoming == b.incoming && a.flux == b.flux && a.uv == b.uv && a.material == b.material &&
         a.bounce == b.bounce && a.radius == b.radius && a.inMedium == b.inMedium && a.medium == b.medium;
}

inline bool sameVpls(const std::vector<Vpl>& a, const std::vector<Vpl>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!sameVpl(a[i], b[i])) return false;
  return true;
}

}  // namespace vplab::test
