#include "renderer/offline/direct_light.h"

#include <cmath>

namespace vplab {

glm::vec3 sampleLightDirect(const EmbreeScene& embree, const LightSampler& lights, const SurfaceHit& hit,
                            const glm::vec3& wo, const BrdfParams& brdf, Rng& rng, uint64_t* shadowRays) {
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
  if (f.r <= 0.0f && f.g <= 0.0f && f.b <= 0.0f) return glm::vec3(0.0f);

  // Exact visibility between the shading point and the light point (both ends nudged off their surfaces); toward a
  // directional light, along wi to infinity.
  ShadowRay ray = std::isinf(ls.distance)
                      ? ShadowRay{embree.offsetOrigin(hit.position, hit.geometricNormal, ls.wi), ls.wi, ls.distance}
                      : embree.shadowRayBetween(hit.position, hit.geometricNormal, ls.position, ls.normal);
  if (shadowRays) ++*shadowRays;
  if (ray.tMax > 0.0f && embree.occluded(ray.origin, ray.direction, ray.tMax)) return glm::vec3(0.0f);

  // Veach's power heuristic against the BRDF pdf of the same direction; a delta light cannot be hit by BRDF
  // sampling, so its weight is 1.
  float weight = ls.isDelta ? 1.0f : powerHeuristic(ls.pdf, brdfPdf(brdf, n, wo, ls.wi));
  return f * ls.radiance * (cosI * weight / ls.pdf);
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
                              const glm::vec3& wo, const BrdfParams& brdf, Rng& rng) {
  // Strategy 1: sample the lights (next-event estimation).
  glm::vec3 result = sampleLightDirect(embree, lights, hit, wo, brdf, rng);

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
  return result + bs.f * le * (cosI / bs.pdf);
}

}  // namespace vplab
