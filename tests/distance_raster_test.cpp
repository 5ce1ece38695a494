// The lights' shadow maps drawn on the CPU (renderer/gl/distance_raster.h) against rays cast through every texel
// centre: the nearest triangle's distance, at most the slope bias more; nothing where no triangle lies; no cracks in a
// closed mesh; the same maps at any thread count.

#include "renderer/gl/distance_raster.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "renderer/core/sampling.h"
#include "tests/nearest_hit.h"

namespace vplab {
namespace {

using test::Nearest;
using test::nearestHit;

// The direction a samplerCube lookup maps to texel (i, j) of face f (GL 4.6 table 8.19), unit length.
glm::dvec3 cubeTexelDirection(int f, int i, int j, int size) {
  const double sc = 2.0 * (i + 0.5) / size - 1.0, tc = 2.0 * (j + 0.5) / size - 1.0;
  const glm::dvec3 d[6] = {{1, -tc, -sc}, {-1, -tc, sc}, {sc, 1, tc}, {sc, -1, -tc}, {sc, -tc, 1}, {-sc, -tc, -1}};
  return glm::normalize(d[f]);
}

void addTriangle(Scene& scene, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  const uint32_t base = static_cast<uint32_t>(scene.positions.size());
  scene.positions.insert(scene.positions.end(), {a, b, c});
  scene.triangles.push_back({base, base + 1, base + 2});
}

// Small triangles all around the origin, large ones spanning several faces and reaching behind the light, one through
// the light's own position's neighbourhood.
Scene scatteredTriangles() {
  Scene scene;
  Rng rng(11);
  auto next3D = [&] { return glm::vec3(rng.next1D(), rng.next1D(), rng.next1D()) - 0.5f; };
  for (int i = 0; i < 400; ++i) {
    const float size = i % 20 == 0 ? 6.0f : 0.4f;
    const glm::vec3 centre = next3D() * 5.0f;
    addTriangle(scene, centre + next3D() * size, centre + next3D() * size, centre + next3D() * size);
  }
  addTriangle(scene, {-3.0f, -0.05f, -3.0f}, {3.0f, -0.05f, -3.0f}, {0.0f, 0.02f, 4.0f});
  return scene;
}

// Every compared texel holds the nearest hit d plus at most maxBias(d); returns how many were compared, and in
// `biased` how many hold more than d.
int compareWithRays(const Scene& scene, const std::vector<float>& map,
                    const std::function<glm::dvec3(int, int)>& origin, const std::function<glm::dvec3(int, int)>& dir,
                    int size, const std::function<double(double)>& maxBias, const std::string& what,
                    int* biased = nullptr) {
  int compared = 0, failures = 0;
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i) {
      const Nearest n = nearestHit(scene, origin(i, j), dir(i, j));
      if (n.ambiguous) continue;
      ++compared;
      const float stored = map[static_cast<std::size_t>(j) * size + i];
      if (!std::isfinite(n.t)) {
        if (stored != kNoOccluder && ++failures <= 5)
          ADD_FAILURE() << what << " texel " << i << "," << j << ": nothing along the ray, stored " << stored;
        continue;
      }
      const double d = n.t;
      if (biased) *biased += stored > d + 1e-4 * d;
      if ((stored < d - 1e-4 * d || stored > d + maxBias(d) + 1e-4 * d) && ++failures <= 5)
        ADD_FAILURE() << what << " texel " << i << "," << j << ": nearest hit at " << d << ", stored " << stored;
    }
  EXPECT_EQ(failures, 0) << what;
  return compared;
}

TEST(DistanceRaster, CubeFacesHoldTheNearestTriangleAlongEveryTexel) {
  const Scene scene = scatteredTriangles();
  const glm::vec3 origin(0.1f, 0.0f, -0.2f);
  const int size = 48;
  const float maxSlopeBias = 8.0f / static_cast<float>(size);
  DistanceRasterizer rasterizer;
  rasterizer.binCube(scene, origin, size, 2);
  ASSERT_EQ(rasterizer.views(), 6);
  std::vector<float> map(static_cast<std::size_t>(size) * size);
  int compared = 0;
  for (int f = 0; f < 6; ++f) {
    rasterizer.draw(f, maxSlopeBias, 2, map.data());
    compared += compareWithRays(
        scene, map, [&](int, int) { return glm::dvec3(origin); },
        [&](int i, int j) { return cubeTexelDirection(f, i, j, size); }, size,
        [&](double d) { return maxSlopeBias * d; }, "face " + std::to_string(f));
  }
  // Few texels lie on an edge.
  EXPECT_GT(compared, 6 * size * size * 95 / 100);
}

TEST(DistanceRaster, RotatedViewsHoldTheNearestTriangleAlongEveryTexelOfTheirRows) {
  // The views of a hemicube around a tilted normal (renderer/gl/shadow_maps.cpp): one along the normal, and side views
  // with the normal up that keep their upper half only.
  const Scene scene = scatteredTriangles();
  const glm::vec3 origin(-0.2f, 0.1f, 0.3f);
  const Frame frame(glm::normalize(glm::vec3(0.3f, 0.9f, -0.2f)));
  const int size = 40;
  const std::vector<DistanceRasterizer::Perspective> views = {
      {frame.s, frame.t, frame.n, 0}, {frame.t, frame.n, frame.s, size / 2}, {frame.s, frame.n, -frame.t, size / 2}};
  DistanceRasterizer rasterizer;
  rasterizer.binPerspective(scene, origin, views, size, 2);
  ASSERT_EQ(rasterizer.views(), 3);
  std::vector<float> map(static_cast<std::size_t>(size) * size);
  int compared = 0;
  for (std::size_t v = 0; v < views.size(); ++v) {
    rasterizer.draw(static_cast<int>(v), 0.0f, 2, map.data());
    const DistanceRasterizer::Perspective& view = views[v];
    for (int j = 0; j < view.firstRow; ++j)
      for (int i = 0; i < size; ++i)
        EXPECT_EQ(map[static_cast<std::size_t>(j) * size + i], kNoOccluder) << "view " << v << " row " << j;
    int failures = 0;
    for (int j = view.firstRow; j < size; ++j)
      for (int i = 0; i < size; ++i) {
        const double x = 2.0 * (i + 0.5) / size - 1.0, y = 2.0 * (j + 0.5) / size - 1.0;
        const glm::dvec3 dir = glm::normalize(glm::dvec3(view.axis) + x * glm::dvec3(view.s) + y * glm::dvec3(view.t));
        const Nearest n = nearestHit(scene, glm::dvec3(origin), dir);
        if (n.ambiguous) continue;
        ++compared;
        const float stored = map[static_cast<std::size_t>(j) * size + i];
        const bool right = std::isfinite(n.t) ? std::abs(stored - n.t) <= 1e-4 * n.t : stored == kNoOccluder;
        if (!right && ++failures <= 5)
          ADD_FAILURE() << "view " << v << " texel " << i << "," << j << ": nearest hit at " << n.t << ", stored "
                        << stored;
      }
  }
  EXPECT_GT(compared, 2 * size * size * 95 / 100);
}

TEST(DistanceRaster, PlaneHoldsTheNearestTriangleAlongEveryTexel) {
  const Scene scene = scatteredTriangles();
  const glm::vec3 direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f)), centre(0.2f, 0.1f, 0.0f);
  // The map covers a sphere holding every triangle (as the scene's bounding sphere does).
  const float radius = 8.0f;
  const int size = 64;
  const float maxSlopeBias = 8.0f * radius / static_cast<float>(size);
  DistanceRasterizer rasterizer;
  rasterizer.binPlane(scene, direction, centre, radius, size, 2);
  std::vector<float> map(static_cast<std::size_t>(size) * size);
  rasterizer.draw(0, maxSlopeBias, 2, map.data());
  const Frame frame(direction);
  const glm::dvec3 plane = glm::dvec3(centre) - glm::dvec3(direction) * static_cast<double>(radius);
  auto texelOrigin = [&](int i, int j) {
    const double x = 2.0 * (i + 0.5) / size - 1.0, y = 2.0 * (j + 0.5) / size - 1.0;
    return plane + static_cast<double>(radius) * (x * glm::dvec3(frame.s) + y * glm::dvec3(frame.t));
  };
  // Distances along the direction from the plane behind the centre; the bias is absolute here (maxSlopeBias metres).
  int biased = 0;
  const int compared = compareWithRays(
      scene, map, texelOrigin, [&](int, int) { return glm::dvec3(direction); }, size,
      [&](double) { return maxSlopeBias; }, "plane", &biased);
  EXPECT_GT(compared, size * size * 95 / 100);
  // Tilted triangles are pushed back by their slope.
  EXPECT_GT(biased, 0);
}

TEST(DistanceRaster, AClosedMeshAroundTheLightLeavesNoTexelEmpty) {
  // A tessellated sphere around the light: every ray meets it, whatever the triangles' size against the texels.
  Scene scene;
  const int rings = 90, segments = 180;
  auto at = [](int r, int s) {
    const float theta = kPi * static_cast<float>(r) / rings, phi = 2.0f * kPi * static_cast<float>(s) / segments;
    return glm::vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)) * 2.0f;
  };
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s < segments; ++s) scene.positions.push_back(at(r, s));
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const uint32_t a = static_cast<uint32_t>(r * segments + s),
                     b = static_cast<uint32_t>(r * segments + (s + 1) % segments), c = a + segments, d = b + segments;
      scene.triangles.push_back({a, b, d});
      scene.triangles.push_back({a, d, c});
    }
  const int size = 256;
  DistanceRasterizer rasterizer;
  rasterizer.binCube(scene, glm::vec3(0.3f, -0.2f, 0.1f), size, 2);
  std::vector<float> map(static_cast<std::size_t>(size) * size);
  for (int f = 0; f < 6; ++f) {
    rasterizer.draw(f, 8.0f / size, 2, map.data());
    int empty = 0;
    for (float v : map) empty += v == kNoOccluder;
    EXPECT_EQ(empty, 0) << "face " << f;
  }
}

TEST(DistanceRaster, TheSameMapsAtAnyThreadCount) {
  const Scene scene = scatteredTriangles();
  const int size = 128;
  auto render = [&](int threads) {
    DistanceRasterizer rasterizer;
    rasterizer.binCube(scene, glm::vec3(0.0f, 0.3f, 0.0f), size, threads);
    std::vector<float> maps(6 * static_cast<std::size_t>(size) * size);
    for (int f = 0; f < 6; ++f)
      rasterizer.draw(f, 8.0f / size, threads, maps.data() + static_cast<std::size_t>(f) * size * size);
    return maps;
  };
  const std::vector<float> one = render(1);
  EXPECT_EQ(render(2), one);
  EXPECT_EQ(render(5), one);
}

}  // namespace
}  // namespace vplab
