#include "ui/vpl_overlay.h"

#include <algorithm>

namespace vplab::ui {

std::vector<bool> vplsSeenByCamera(const EmbreeScene& embree, const Camera& camera, const std::vector<Vpl>& vpls) {
  std::vector<bool> seen(vpls.size(), false);
  for (std::size_t i = 0; i < vpls.size(); ++i) {
    const glm::vec3 d = vpls[i].position - camera.position;
    if (glm::dot(d, camera.forward) <= camera.znear) continue;
    // The camera end has no surface: its offset goes toward the VPL.
    seen[i] = embree.visible(camera.position, glm::normalize(d), vpls[i].position, vpls[i].geometricNormal);
  }
  return seen;
}

double seenShare(const std::vector<bool>& seen) {
  if (seen.empty()) return 0.0;
  return static_cast<double>(std::count(seen.begin(), seen.end(), true)) / static_cast<double>(seen.size());
}

}  // namespace vplab::ui
