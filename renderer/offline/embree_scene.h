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

/// Where a ray segment through surfaces and media ends (EmbreeScene::traceSegment, docs/theory.md §16).
struct Segment {
  enum class End {
    Surface,  ///< reached the closest surface `hit`
    Medium,   ///< scattered in media[medium] at `position`
    Escape,   ///< left the scene (no surface before tMax, no scattering event)
  };
  End end = End::Escape;
  std::optional<SurfaceHit> hit;  ///< End::Surface
  glm::vec3 position{0.0f};       ///< End::Medium: the scattering point (End::Surface: the hit's position)
  float distance = 0.0f;          ///< ray parameter of the end (infinite for Escape)
  /// Ray parameter of the closest surface (tMax when there is none), also when the segment scattered before it.
  float surfaceDistance = 0.0f;
  uint32_t medium = 0;            ///< End::Medium
  /// The free-flight estimator's weight (spectral MIS over the channels): T(t) sigma_s / pdf(t) for a scattering
  /// event, T(s) / P(no event before s) for a surface or an escape. Exactly 1 when the segment crosses no medium.
  glm::vec3 weight{1.0f};
  /// What spectral MIS over a whole path needs of the flight (FreeFlight::f and ::p, media_tracking.h): weight is
  /// spectralF / mean(spectralP). In homogeneous media spectralF is T sigma_s at a scattering event and T otherwise.
  glm::vec3 spectralF{1.0f};
  glm::vec3 spectralP{1.0f};
  bool crossedMedium = false;  ///< the segment overlaps a medium (and two random numbers were drawn)
  bool scattered() const { return end == End::Medium; }
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

  /// The one way a path moves through the scene: the closest surface along origin + t * direction (unit), t in
  /// (0, tMax), and where the segment overlaps media, a free flight sampled with two random numbers drawn from
  /// `draw` (spectral MIS: a channel picked uniformly, the distance from its sigma_t, weighted by the mean of the
  /// three channels' pdfs; docs/theory.md §16). Without media on the segment no number is drawn and the result is
  /// exactly intersect()'s, so media-free paths keep their random streams.
  template <class DrawPair>
  Segment traceSegment(const glm::vec3& origin, const glm::vec3& direction, float tMax, DrawPair&& draw) const {
    Segment s = beginSegment(origin, direction, tMax);
    if (s.crossedMedium) sampleFreeFlight(s, origin, direction, draw());
    return s;
  }
  /// Transmittance of the media along origin + t * direction, t in [0, tMax) (occlusion not tested); (1, 1, 1)
  /// without media.
  glm::vec3 transmittance(const glm::vec3& origin, const glm::vec3& direction, float tMax) const;
  /// A shadow ray's transmittance: 0 when it is occluded, the media's transmittance along it otherwise.
  /// mediumTMax, when finite, ends the media's part earlier (a directional light's light enters them at its disk).
  glm::vec3 shadowTransmittance(const ShadowRay& ray, float mediumTMax = -1.0f) const;
  /// True when the scene holds media that absorb or scatter.
  bool hasMedia() const { return hasMedia_; }

  /// Scene-scale length used for ray offsets.
  float rayEpsilon() const { return rayEpsilon_; }

 private:
  Segment beginSegment(const glm::vec3& origin, const glm::vec3& direction, float tMax) const;
  void sampleFreeFlight(Segment& s, const glm::vec3& origin, const glm::vec3& direction, glm::vec2 u) const;

  struct Impl;
  const Scene& scene_;
  bool hasMedia_ = false;
  std::unique_ptr<Impl> impl_;
  float rayEpsilon_ = 1e-4f;
};

}  // namespace vplab
