#include "renderer/offline/medium_direct.h"

#include <algorithm>
#include <cmath>

#include "renderer/offline/camera_sample.h"
#include "renderer/offline/direct_light.h"
#include "renderer/offline/interaction.h"
#include "renderer/offline/media_tracking.h"

namespace vplab {

MediumLightSegment::MediumLightSegment(const EmbreeScene& embree, const glm::vec3& origin, const glm::vec3& direction,
                                       float end, bool forced, const glm::vec3& channelWeights,
                                       DistanceSampling techniques, bool mixedDirections)
    : embree_(embree), forced_(forced), techniques_(techniques), mixedDirections_(mixedDirections) {
  reset(origin, direction, end, channelWeights);
}

MediumLightSegment::MediumLightSegment(const EmbreeScene& embree, const glm::vec3& origin, const glm::vec3& direction,
                                       float end, const std::vector<MediumInterval>& intervals)
    : embree_(embree), origin_(origin), direction_(direction), end_(end), forced_(true), intervals_(intervals) {
  setSpan();
}

void MediumLightSegment::reset(const glm::vec3& origin, const glm::vec3& direction, float end,
                               const glm::vec3& channelWeights) {
  origin_ = origin;
  direction_ = direction;
  end_ = end;
  channelWeights_ = channelWeights;
  intervals_.clear();
  if (!embree_.hasMedia()) return;
  mediumIntervals(embree_.scene().media, origin, direction, end, intervals_);
  setSpan();
}

void MediumLightSegment::setSpan() {
  if (intervals_.empty()) return;
  const Scene& scene = embree_.scene();
  // The span equiangular sampling covers: from the first medium interval to the last one's end (a medium filling all
  // space is cut where its light has faded, mediaSpanEnd; beyond, p_eq = 0 and the free flight alone counts).
  const float diagonal = std::max(scene.bounds.diagonal(), 1e-6f);
  a_ = intervals_.front().t0;
  b_ = mediaSpanEnd(scene.media, intervals_, end_, diagonal);
  minH_ = 1e-6f * diagonal;
}

float MediumLightSegment::flightPdf(float t) const {
  return flightDensity(embree_.scene().media, intervals_, origin_, direction_, end_, t, forced_, channelWeights_);
}

float MediumLightSegment::flightWeight(const glm::vec3& position, const glm::vec3* lightPoint, bool pointLight) const {
  if (techniques_ == DistanceSampling::FreeFlight || !lightPoint || !(b_ > a_)) return 1.0f;
  const float t = glm::dot(position - origin_, direction_);
  const float pdfEq = equiangularPdf(origin_, direction_, a_, b_, *lightPoint, minH_, t);
  if (techniques_ == DistanceSampling::Equiangular) return pdfEq > 0.0f ? 0.0f : 1.0f;
  // A point or spot light: both techniques every time, power heuristic; where equiangular sampling cannot reach t, the
  // free flight carries the whole integrand.
  if (pointLight) return pdfEq > 0.0f ? powerHeuristic(flightPdf(t), pdfEq) : 1.0f;
  // An area light: one of the two, by the segment's coin (balance heuristic over the choice, divided by its
  // probability: 1 / c_ff where equiangular sampling cannot reach t).
  if (equiangularChosen_) return 0.0f;
  const float pdfFf = flightPdf(t);
  const float cEq = kAreaEquiangularProbability;
  return pdfFf / ((1.0f - cEq) * pdfFf + cEq * pdfEq);
}

glm::vec3 MediumLightSegment::equiangular(const LightSampler& lights, Rng& rng, uint64_t* shadowRays) const {
  // Step 1: the light point first, with the numbers next-event estimation will use at x(t) (so it picks the same c);
  // for an area light, uT also tosses the segment's coin between the two techniques.
  const float uLight = rng.next1D();
  const glm::vec2 uPoint = rng.next2D();
  float uT = rng.next1D();
  const float cEq = kAreaEquiangularProbability;
  equiangularChosen_ = uT < cEq;
  if (techniques_ == DistanceSampling::FreeFlight || !(b_ > a_) || lights.empty()) return glm::vec3(0.0f);
  glm::vec3 c;
  bool pointLight = false;
  if (!lights.samplePosition(uLight, uPoint, c, &pointLight)) return glm::vec3(0.0f);  // directional: no point
  const bool oneSample = techniques_ == DistanceSampling::Mis && !pointLight;
  if (oneSample) {
    if (!equiangularChosen_) return glm::vec3(0.0f);
    uT /= cEq;
  }
  // Step 2: t equiangular around c over the media span (Kulla & Fajardo 2012); nothing between media boxes.
  float t = 0.0f, pdfEq = 0.0f;
  const MediumInterval* in = sampleEquiangular(intervals_, origin_, direction_, a_, b_, c, uT, minH_, t, pdfEq);
  if (!in) return glm::vec3(0.0f);
  // Step 3: the MIS weight against the free flight's density at t: the power heuristic for a point or spot light, the
  // one-sample balance heuristic divided by the coin's probability for an area light.
  float weight = 1.0f;
  if (techniques_ == DistanceSampling::Mis) {
    const float pdfFf = flightPdf(t);
    weight = oneSample ? pdfEq / ((1.0f - cEq) * pdfFf + cEq * pdfEq) : powerHeuristic(pdfEq, pdfFf);
  }
  if (!(weight > 0.0f)) return glm::vec3(0.0f);
  // Step 4: next-event estimation toward c at x(t), times sigma_s(x) T(o, t) / p_eq (T ratio-tracked through grids).
  const Scene& scene = embree_.scene();
  const Interaction x = Interaction::inMediumAt(scene, origin_ + direction_ * t, in->medium, -direction_);
  if (!(x.sigmaS.r > 0.0f || x.sigmaS.g > 0.0f || x.sigmaS.b > 0.0f)) return glm::vec3(0.0f);
  const glm::vec3 nee = sampleLightMedium(embree_, lights, x, uLight, uPoint, shadowRays, nullptr, mixedDirections_);
  if (!(nee.r > 0.0f || nee.g > 0.0f || nee.b > 0.0f)) return glm::vec3(0.0f);
  const glm::vec3 tr = transmittanceAlong(scene.media, intervals_, origin_, direction_, t);
  return nee * x.sigmaS * tr * (weight / pdfEq);
}

}  // namespace vplab
