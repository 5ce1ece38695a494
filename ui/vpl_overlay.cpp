#include "ui/vpl_overlay.h"

#include <algorithm>
#include <cmath>

namespace vplab::ui {

std::optional<glm::vec2> projectToImage(const Camera& camera, float aspect, const glm::vec3& p) {
  const glm::vec3 d = p - camera.position;
  const float z = glm::dot(d, camera.forward);
  if (!(z > camera.znear)) return std::nullopt;
  const float tanHalf = std::tan(0.5f * camera.yfov);
  return glm::vec2(glm::dot(d, camera.right()) / (z * tanHalf * aspect), glm::dot(d, camera.up) / (z * tanHalf));
}

std::vector<std::array<glm::vec2, 2>> mediumBoxOutline(const Medium& medium, const Camera& camera, float aspect) {
  std::vector<std::array<glm::vec2, 2>> edges;
  const std::vector<glm::vec3> corners = medium.corners();
  if (corners.empty()) return edges;
  // Corner i lies at +1 along the box's axis a where bit a of i is set: an edge joins two corners one bit apart.
  for (int i = 0; i < 8; ++i)
    for (int bit = 1; bit < 8; bit <<= 1) {
      if (i & bit) continue;
      glm::vec3 a = corners[i], b = corners[i | bit];
      // Heights over the near plane; an end behind it moves to just in front of it along the edge.
      const float ha = glm::dot(a - camera.position, camera.forward) - camera.znear;
      const float hb = glm::dot(b - camera.position, camera.forward) - camera.znear;
      if (!(ha > 0.0f) && !(hb > 0.0f)) continue;
      constexpr float kInFront = 0.999f;  // of the way from the end in front to the plane
      if (!(ha > 0.0f)) a = b + (a - b) * (kInFront * hb / (hb - ha));
      if (!(hb > 0.0f)) b = a + (b - a) * (kInFront * ha / (ha - hb));
      const std::optional<glm::vec2> pa = projectToImage(camera, aspect, a), pb = projectToImage(camera, aspect, b);
      if (pa && pb) edges.push_back({*pa, *pb});
    }
  return edges;
}

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
