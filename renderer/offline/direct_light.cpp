#include "renderer/offline/direct_light.h"

#include <cmath>

#include "renderer/offline/medium_direct.h"

namespace vplab {

glm::vec3 sampleLightDirect(const EmbreeScene& embree, const LightSampler& lights, const SurfaceHit& hit,
                            const glm::vec3& wo, const BrdfParams& brdf, Rng& rng, uint64_t* shadowRays,
                            IncidentSample* incident, bool mixed) {
  // Draw the random numbers first so the stream advances by the same amount whatever happens below.
  float uLight = rng.next1D();
  glm::vec2 uPoint = rng.next2D();
  if (lights.empty() || !facesDirection(hit, wo)) return glm::vec3(0.0f);

  // Light chosen by power, point uniform on its area; pdf converted to solid angle (pdf_A d^2 / cos_light).
  LightSampleLi ls = lights.sampleLi(hit.position, uLight, uPoint);
  if (!ls.valid() || !facesDirection(hit, ls.wi)) return glm::vec3(0.0f);
  const glm::vec3& n = hit.shadingNormal;
  float cosI = glm::dot(n, ls.wi);
  if (cosI <= 0.0f) return glm::vec3(0.0f);
  glm::vec3 f = evaluateBrdf(brdf, n, wo, ls.wi);
  // Nothing to reflect toward wo: no shadow ray, unless the sample is kept for other viewers.
  if (!incident && f.r <= 0.0f && f.g <= 0.0f && f.b <= 0.0f) return glm::vec3(0.0f);

  // Exact visibility between the shading point and the light point (both ends nudged off their surfaces); toward a
  // directional light, along wi to infinity.
  ShadowRay ray = std::isinf(ls.distance)
                      ? ShadowRay{embree.offsetOrigin(hit.position, hit.geometricNormal, ls.wi), ls.wi, ls.distance}
                      : embree.shadowRayBetween(hit.position, hit.geometricNormal, ls.position, ls.normal);
  if (shadowRays) ++*shadowRays;
  if (!embree.hasMedia()) {
    if (ray.tMax > 0.0f && embree.occluded(ray.origin, ray.direction, ray.tMax)) return glm::vec3(0.0f);
  }
  // With media, the light is attenuated by their transmittance along the shadow ray (docs/theory.md §16).
  const glm::vec3 tr = embree.hasMedia() ? embree.shadowTransmittance(ray, ls.mediumDistance) : glm::vec3(1.0f);

  // Veach's power heuristic against the BRDF pdf of the same direction; a delta light cannot be hit by BRDF
  // sampling, so its weight is 1.
  float weight = 1.0f;
  if (!ls.isDelta) {
    const float scatterPdf = brdfPdf(brdf, n, wo, ls.wi);
    weight = powerHeuristic(ls.pdf, mixed ? lights.mixedScatterPdf(hit.position, ls.wi, scatterPdf) : scatterPdf);
  }
  glm::vec3 result = f * ls.radiance * (cosI * weight / ls.pdf);
  if (incident) *incident = {ls.wi, ls.radiance * (cosI * weight / ls.pdf) * tr};
  return embree.hasMedia() ? result * tr : result;
}

glm::vec3 sampleLightDirect(const EmbreeScene& embree, const LightSampler& lights, const Interaction& it, Rng& rng,
                            uint64_t* shadowRays, const MediumLightSegment* along, bool mixed) {
  if (!it.inMedium) return sampleLightDirect(embree, lights, it.hit, it.wo, it.brdf, rng, shadowRays, nullptr, mixed);
  float uLight = rng.next1D();
  glm::vec2 uPoint = rng.next2D();
  return sampleLightMedium(embree, lights, it, uLight, uPoint, shadowRays, along, mixed);
}

glm::vec3 sampleLightMedium(const EmbreeScene& embree, const LightSampler& lights, const Interaction& it, float uLight,
                            glm::vec2 uPoint, uint64_t* shadowRays, const MediumLightSegment* along, bool mixed) {
  if (lights.empty()) return glm::vec3(0.0f);
  // The same light sample as on a surface; the phase function instead of f cos, no side to face.
  LightSampleLi ls = lights.sampleLi(it.position, uLight, uPoint);
  if (!ls.valid()) return glm::vec3(0.0f);
  // The distance MIS weight of the free flight that found this point, against equiangular sampling toward the light
  // point (docs/theory.md §24); a directional light has no point and keeps weight 1.
  const bool hasPoint = !std::isinf(ls.distance);
  const float distanceWeight =
      along ? along->flightWeight(it.position, hasPoint ? &ls.position : nullptr, ls.isDelta) : 1.0f;
  if (!(distanceWeight > 0.0f)) return glm::vec3(0.0f);
  const float phase = phaseHG(it.wo, ls.wi, it.g);
  ShadowRay ray = std::isinf(ls.distance) ? ShadowRay{it.position, ls.wi, ls.distance}
                                          : embree.shadowRayBetween(it.position, glm::vec3(0.0f), ls.position,
                                                                    ls.normal);
  if (shadowRays) ++*shadowRays;
  const glm::vec3 tr = embree.shadowTransmittance(ray, ls.mediumDistance);
  if (tr.r <= 0.0f && tr.g <= 0.0f && tr.b <= 0.0f) return glm::vec3(0.0f);
  // MIS against phase-function sampling of the same direction (power heuristic), delta lights unweighted.
  float weight =
      ls.isDelta ? 1.0f : powerHeuristic(ls.pdf, mixed ? lights.mixedScatterPdf(it.position, ls.wi, phase) : phase);
  return tr * ls.radiance * (phase * weight * distanceWeight / ls.pdf);
}

glm::vec3 misWeightedEmission(const LightSampler& lights, const glm::vec3& from, const SurfaceHit& emitterHit,
                              const glm::vec3& wi, float brdfPdf) {
  // One-sided emitters: Le only toward the side the winding normal faces.
  glm::vec3 le = lights.emittedRadiance(emitterHit.triangle, emitterHit.geometricNormal, emitterHit.uv, -wi);
  if (le.r <= 0.0f && le.g <= 0.0f && le.b <= 0.0f) return glm::vec3(0.0f);
  // The solid-angle pdf with which next-event estimation would have produced this point: power heuristic.
  float lightPdf = lights.pdfLi(from, emitterHit.triangle, emitterHit.position, emitterHit.geometricNormal);
  return le * powerHeuristic(brdfPdf, lightPdf);
}

glm::vec3 estimateDirectLight(const EmbreeScene& embree, const LightSampler& lights, const SurfaceHit& hit,
                              const glm::vec3& wo, const BrdfParams& brdf, Rng& rng,
                              std::array<IncidentSample, 2>* incident) {
  if (incident) *incident = {};
  // Strategy 1: sample the lights (next-event estimation).
  glm::vec3 result = sampleLightDirect(embree, lights, hit, wo, brdf, rng, nullptr, incident ? &(*incident)[0] : nullptr);

  // Strategy 2: sample the BRDF and trace the ray; it counts only if it lands on an emitter.
  glm::vec3 u(rng.next1D(), rng.next1D(), rng.next1D());
  if (lights.empty() || !facesDirection(hit, wo)) return result;
  BrdfSample bs = sampleBrdf(brdf, hit.shadingNormal, wo, u);
  if (!bs.valid() || !facesDirection(hit, bs.wi)) return result;
  glm::vec3 origin = embree.offsetOrigin(hit.position, hit.geometricNormal, bs.wi);
  std::optional<SurfaceHit> next = embree.intersect(origin, bs.wi);
  if (!next) return result;
  float cosI = glm::dot(hit.shadingNormal, bs.wi);
  glm::vec3 le = misWeightedEmission(lights, hit.position, *next, bs.wi, bs.pdf);
  // Light from the emitter crosses the media on the way (their transmittance, not a free flight: this estimator
  // counts only light that comes straight from the emitter).
  if (embree.hasMedia()) le *= embree.transmittance(origin, bs.wi, next->distance);
  if (incident) (*incident)[1] = {bs.wi, le * (cosI / bs.pdf)};
  return result + bs.f * le * (cosI / bs.pdf);
}

glm::vec3 estimateDirectLight(const EmbreeScene& embree, const LightSampler& lights, const Interaction& it, Rng& rng,
                              const MediumLightSegment* along) {
  if (!it.inMedium) return estimateDirectLight(embree, lights, it.hit, it.wo, it.brdf, rng);
  glm::vec3 result = sampleLightDirect(embree, lights, it, rng, nullptr, along);
  glm::vec2 u = rng.next2D();
  if (lights.empty()) return result;
  PhaseSample ps = samplePhaseHG(it.wo, it.g, u);
  std::optional<SurfaceHit> next = embree.intersect(it.position, ps.wi);
  if (!next) return result;
  glm::vec3 le = misWeightedEmission(lights, it.position, *next, ps.wi, ps.pdf);
  // f_p / pdf = 1: the phase function is sampled exactly.
  return result + le * embree.transmittance(it.position, ps.wi, next->distance);
}

}  // namespace vplab
