#pragma once
// The Scene as an Embree 3 BVH: closest-hit and occlusion queries for every CPU pass.

#include "renderer/scene/scene.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <memory>
#include <optional>

namespace vplab {

struct SurfaceHit {
  float distance = 0.0f;
  uint32_t triangle = 0;
  uint32_t material = 0;
  glm::vec3 position{0.0f};
  glm::vec3 geometricNormal{0.0f};  ///< unit, on the side the triangle's vertex normals point to
  glm::vec3 shadingNormal{0.0f};    ///< unit, interpolated vertex normal
  glm::vec2 uv{0.0f};
};

/// A shadow ray from origin along a unit direction up to tMax (exclusive of the end point's surface).
struct ShadowRay {
  glm::vec3 origin{0.0f};
  glm::vec3 direction{0.0f, 0.0f, 1.0f};
  float tMax = 0.0f;
};

class EmbreeScene {
 public:
  /// Builds the BVH. The scene must outlive this object.
  explicit EmbreeScene(const Scene& scene);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  const Scene& scene() const { return scene_; }

  /// Closest hit along origin + t * direction for t in (0, tMax); direction need not be unit (distance is in t).
  std::optional<SurfaceHit> intersect(const glm::vec3& origin, const glm::vec3& direction,
                                      float tMax = std::numeric_limits<float>::infinity()) const;
  /// True when anything lies along origin + t * direction for t in (0, tMax).
  bool occluded(const glm::vec3& origin, const glm::vec3& direction, float tMax) const;
  /// Occlusion of `count` rays, traced in 8-wide packets; occludedOut[i] is 1 when ray i is blocked.
  void occludedBatch(const ShadowRay* rays, uint8_t* occludedOut, std::size_t count) const;

  /// Origin for a ray leaving a surface point along dir: nudged off the surface along the geometric normal to
  /// avoid self-intersection (offset proportional to the scene size).
  glm::vec3 offsetOrigin(const glm::vec3& p, const glm::vec3& geometricNormal, const glm::vec3& dir) const;
  /// Shadow ray between two surface points, both ends nudged off their surfaces.
  ShadowRay shadowRayBetween(const glm::vec3& p0, const glm::vec3& n0, const glm::vec3& p1,
                             const glm::vec3& n1) const;
  /// True when the segment between two surface points is unoccluded.
  bool visible(const glm::vec3& p0, const glm::vec3& n0, const glm::vec3& p1, const glm::vec3& n1) const;

  /// Scene-scale length used for ray offsets.
  float rayEpsilon() const { return rayEpsilon_; }

 private:
  struct Impl;
  const Scene& scene_;
  std::unique_ptr<Impl> impl_;
  float rayEpsilon_ = 1e-4f;
};

}  // namespace vplab
