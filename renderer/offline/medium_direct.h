#pragma once
// Distance sampling toward the lights along a ray segment through media (docs/theory.md §24; Kulla & Fajardo 2012, as
// Cycles does on every volume segment). The light arriving at the segment's medium points from next-event estimation,
//   integral_0^s T(o, x(t)) sigma_s(x(t)) [sum over the light sample of f_p Le G V T w_light] dt,
// is estimated by two techniques combined by MIS:
//   - free flight: the point the segment's own free flight scattered at (the path's vertex), its next-event estimate
//     times w_ff(t | c), c the light point that estimate drew;
//   - equiangular: a light point c drawn first (as next-event estimation draws it: the light by power, the point
//     uniform on its area, neither depending on the receiver), then t equiangularly around c over the segment's media
//     span, weight sigma_s T(o, t) / p_eq(t | c) times the next-event estimate toward c at x(t) times w_eq(t | c).
// For a point or spot light both techniques take their sample, w = the power heuristic (p_ff^2 / (p_ff^2 + p_eq^2));
// for an area light a coin picks one of them per segment (probability kAreaEquiangularProbability for equiangular),
// w_i / c_i with the balance heuristic over c_i p_i (one-sample MIS, Veach 1997 §9.2.4). T is ratio-tracked through
// grids.
// p_ff is flightDensity() (media_tracking.h): exact for homogeneous media and for the forced flights of the VPL and VRL
// renders, a fixed approximation for the reference's delta-tracked flights through grids. The phase-function half of
// the direction MIS (the emitter a phase-sampled ray finds) stays with the free-flight point alone.

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "renderer/core/sampling.h"
#include "renderer/offline/direct_light.h"
#include "renderer/offline/embree_scene.h"
#include "renderer/offline/interaction.h"
#include "renderer/offline/light_sampler.h"
#include "renderer/offline/media_tracking.h"
#include "renderer/scene/medium.h"

namespace vplab {

/// Which distance-sampling techniques estimate the lights' single scattering along a segment: both by MIS (what the
/// renderers use), or one alone (for tests: each alone is unbiased as well).
enum class DistanceSampling { Mis, FreeFlight, Equiangular };

class MediumLightSegment {
 public:
  /// The segment origin + t * direction (unit), t in [0, end) (end may be infinite). forced: its free-flight point was
  /// drawn by sampleForcedFlight() (else by the path's sampleFlight(), with channelWeights the path's spectral MIS
  /// channel probabilities before this segment).
  /// mixedDirections: the phase-sampled half of the direction MIS samples by LightSampler::mixedScatterPdf() (the
  /// reference's paths), so the equiangular point's next-event estimate weighs against that density.
  MediumLightSegment(const EmbreeScene& embree, const glm::vec3& origin, const glm::vec3& direction, float end,
                     bool forced, const glm::vec3& channelWeights = glm::vec3(1.0f),
                     DistanceSampling techniques = DistanceSampling::Mis, bool mixedDirections = false);

  /// The same for a forced flight's segment whose media intervals the caller has (mediumIntervals() of that segment).
  MediumLightSegment(const EmbreeScene& embree, const glm::vec3& origin, const glm::vec3& direction, float end,
                     const std::vector<MediumInterval>& intervals);

  /// Moves to another segment of the same scene, flight kind and techniques, keeping the storage.
  void reset(const glm::vec3& origin, const glm::vec3& direction, float end, const glm::vec3& channelWeights);
  /// No segment at all: overlapsMedia() is false until the next reset().
  void clear() { intervals_.clear(); }

  /// True when the segment overlaps a medium (otherwise there is nothing to estimate).
  bool overlapsMedia() const { return !intervals_.empty(); }
  /// The free-flight technique's MIS weight for its point at `position` whose next-event estimate drew the light
  /// point `lightPoint` (null: a directional light, which equiangular sampling does not serve: weight 1) of a point or
  /// spot light (pointLight) or an emitting triangle. Call after equiangular(), which tosses the segment's coin.
  float flightWeight(const glm::vec3& position, const glm::vec3* lightPoint, bool pointLight) const;
  /// The equiangular technique's estimate (the MIS weight included). Draws four numbers (the light, its point, t)
  /// whatever happens; shadowRays counts the shadow ray it traces.
  glm::vec3 equiangular(const LightSampler& lights, Rng& rng, uint64_t* shadowRays = nullptr) const;

  /// Probability with which a segment estimates an area light's single scattering by equiangular sampling rather than
  /// at its free-flight point (one-sample MIS: either costs one shadow ray, and an area light's 1/d^2 is spread over
  /// its area). Point and spot lights take both samples.
  static constexpr float kAreaEquiangularProbability = 0.5f;

 private:
  /// The span equiangular sampling covers, from intervals_.
  void setSpan();
  float flightPdf(float t) const;

  const EmbreeScene& embree_;
  glm::vec3 origin_, direction_;
  float end_ = 0.0f;
  float a_ = 0.0f, b_ = 0.0f;  ///< the media span equiangular sampling covers
  float minH_ = 0.0f;
  bool forced_ = false;
  glm::vec3 channelWeights_{1.0f};
  DistanceSampling techniques_ = DistanceSampling::Mis;
  bool mixedDirections_ = false;
  mutable bool equiangularChosen_ = false;  ///< the segment's coin for area lights, tossed by equiangular()
  std::vector<MediumInterval> intervals_;
};

/// The media part of a camera ray o + t d of the VPL and VRL renders at one forced free flight before `end`
/// (sampleForcedFlight, docs/theory.md §17): T sigma_s / pdf times, when `direct`, the lights' single scattering there
/// (estimateDirectLight, its light half weighted against equiangular sampling) plus atFlight(x), the method's own light
/// at that point; when `direct`, plus the ray's equiangular estimate. Draws 2, then 4 and 5 (direct), then atFlight's
/// numbers; nothing more when no channel can scatter before `end`.
template <class AtFlight>
glm::vec3 forcedFlightAlongRay(const EmbreeScene& embree, const LightSampler& lights, const glm::vec3& o,
                               const glm::vec3& d, const std::vector<MediumInterval>& intervals, float end, bool direct,
                               Rng& rng, AtFlight&& atFlight, uint64_t* shadowRays = nullptr) {
  const Scene& scene = embree.scene();
  // Step 1: one distance by a free flight forced to scatter before `end`.
  const glm::vec2 u = rng.next2D();
  float t = 0.0f;
  uint32_t medium = 0;
  glm::vec3 weight(0.0f);
  if (!sampleForcedFlight(scene.media, intervals, o, d, end, u, t, medium, weight)) return glm::vec3(0.0f);
  const Interaction x = Interaction::inMediumAt(scene, o + d * t, medium, -d);
  if (!direct) return weight * atFlight(x);
  // Step 2: the equiangular technique's sample toward the light it draws (it tosses the segment's coin first).
  const MediumLightSegment along(embree, o, d, end, intervals);
  const glm::vec3 equiangular = along.equiangular(lights, rng, shadowRays);
  // Step 3: the lights' single scattering at the flight, its light half MIS-weighted against equiangular sampling,
  // then the method's own light there.
  glm::vec3 l = estimateDirectLight(embree, lights, x, rng, &along);
  l += atFlight(x);
  return weight * l + equiangular;
}

}  // namespace vplab
