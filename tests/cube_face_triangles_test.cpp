// The per-face triangle lists of the lights' cube maps (renderer/gl/light_shadows.h cubeFaceTriangles): a face's list
// holds every triangle with a point inside the face's frustum (so the map is the one every triangle gives), keeps the
// scene's order, and leaves out most of the others.

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "renderer/core/sampling.h"
#include "renderer/gl/light_shadows.h"

namespace vplab {
namespace {

// Whether d (relative to the cube's centre) lies strictly inside face f's frustum (GL's face order).
bool insideFace(glm::vec3 d, int f) {
  const int a = f / 2, b = (a + 1) % 3, c = (a + 2) % 3;
  const float u = f % 2 ? -d[a] : d[a];
  return u > std::abs(d[b]) && u > std::abs(d[c]);
}

TEST(CubeFaceTriangles, EveryTriangleReachingAFaceIsInItsList) {
  Scene scene;
  Rng rng(7);
  auto next3D = [&] { return glm::vec3(rng.next1D(), rng.next1D(), rng.next1D()); };
  // Small triangles all around the origin, and large ones that span several faces without a vertex inside them.
  for (int i = 0; i < 3000; ++i) {
    const float size = i % 10 == 0 ? 3.0f : 0.1f;
    const glm::vec3 centre = (next3D() - 0.5f) * 4.0f;
    const uint32_t base = static_cast<uint32_t>(scene.positions.size());
    for (int v = 0; v < 3; ++v) scene.positions.push_back(centre + (next3D() - 0.5f) * size);
    scene.triangles.push_back({base, base + 1, base + 2});
  }
  const glm::vec3 origin(0.1f, -0.2f, 0.05f);
  const CubeFaceTriangles lists = cubeFaceTriangles(scene, origin);
  std::size_t listed = 0;
  for (int f = 0; f < 6; ++f) {
    std::set<std::size_t> inList;
    std::size_t previous = 0;
    for (std::size_t j = lists.begin[f]; j < lists.begin[f + 1]; j += 3) {
      // Each entry is one of the scene's triangles, in the scene's order.
      const auto it = std::find_if(scene.triangles.begin() + static_cast<std::ptrdiff_t>(previous),
                                   scene.triangles.end(), [&](const glm::uvec3& t) { return t.x == lists.indices[j]; });
      ASSERT_NE(it, scene.triangles.end()) << "face " << f;
      previous = static_cast<std::size_t>(it - scene.triangles.begin());
      ASSERT_EQ(*it, glm::uvec3(lists.indices[j], lists.indices[j + 1], lists.indices[j + 2]));
      inList.insert(previous);
    }
    listed += inList.size();
    for (std::size_t t = 0; t < scene.triangles.size(); ++t) {
      const glm::uvec3& tri = scene.triangles[t];
      bool reaches = false;
      for (int s = 0; s < 64 && !reaches; ++s) {
        const glm::vec2 b = sampleUniformTriangle(rng.next2D());
        const glm::vec3 p =
            b.x * scene.positions[tri.x] + b.y * scene.positions[tri.y] + (1.0f - b.x - b.y) * scene.positions[tri.z];
        reaches = insideFace(p - origin, f);
      }
      if (reaches) EXPECT_TRUE(inList.count(t)) << "triangle " << t << " reaches face " << f << " but is not listed";
    }
  }
  // Small triangles reach one face, rarely two; large ones several: far fewer than six lists of everything.
  std::printf("[ measured ] cube face lists: %.2f faces per triangle\n",
              static_cast<double>(listed) / static_cast<double>(scene.triangles.size()));
  EXPECT_LT(listed, 2 * scene.triangles.size());
}

}  // namespace
}  // namespace vplab
