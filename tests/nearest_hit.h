#pragma once
// The nearest triangle along a ray, cast in double over every triangle of a scene: what the tests of the CPU-drawn
// shadow maps (distance_raster_test.cpp, gl_vpl_maps_test.cpp) compare each texel with.

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <limits>
#include <optional>

#include "renderer/scene/scene.h"

namespace vplab::test {

// Ray-triangle hit (Moller-Trumbore in double): the distance along the unit direction, and the smallest barycentric
// coordinate (negative: outside).
struct RayHit {
  double t = 0.0, minBarycentric = -1.0;
};
inline std::optional<RayHit> castRay(glm::dvec3 origin, glm::dvec3 dir, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
  const glm::dvec3 e1 = b - a, e2 = c - a, p = glm::cross(dir, e2);
  const double det = glm::dot(e1, p);
  if (std::abs(det) < 1e-18) return std::nullopt;
  const glm::dvec3 s = origin - a, q = glm::cross(s, e1);
  const double u = glm::dot(s, p) / det, v = glm::dot(dir, q) / det, t = glm::dot(e2, q) / det;
  if (t <= 0.0) return std::nullopt;
  return RayHit{t, std::min({u, v, 1.0 - u - v})};
}

// The nearest hit beyond minT along a ray over every triangle; `ambiguous` when a triangle's edge passes so close to
// the ray that rounding may decide either way (those texels are not compared).
struct Nearest {
  double t = std::numeric_limits<double>::infinity();
  bool ambiguous = false;
};
inline Nearest nearestHit(const Scene& scene, glm::dvec3 origin, glm::dvec3 dir, double minT = 0.0) {
  Nearest n;
  for (const glm::uvec3& tri : scene.triangles) {
    const auto hit = castRay(origin, dir, scene.positions[tri.x], scene.positions[tri.y], scene.positions[tri.z]);
    if (!hit || hit->t <= minT) continue;
    if (std::abs(hit->minBarycentric) < 1e-4) n.ambiguous = true;
    if (hit->minBarycentric >= 0.0) n.t = std::min(n.t, hit->t);
  }
  return n;
}

}  // namespace vplab::test
