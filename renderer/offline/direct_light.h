#pragma once
// Direct light at a surface point, the reference's own estimator, shared with the exact VPL renderer so that both
// count direct light identically: next-event estimation to area and punctual lights combined with BRDF sampling by
// multiple importance sampling (Veach 1997, ch. 9, power heuristic with beta = 2). Emitters are one-sided and every
// shadow ray is traced exactly.

#include "renderer/core/brdf.h"
#include "renderer/core/sampling.h"
#include "renderer/offline/embree_scene.h"
#include "renderer/offline/interaction.h"
#include "renderer/offline/light_sampler.h"

#include <glm/glm.hpp>

#include <array>
#include <cstdint>

namespace vplab {

/// True when a surface hit reflects toward w: vplab's surfaces are one-sided, so w must lie on the side of the
/// geometric normal (the shading normal then decides the BRDF's cosines).
inline bool facesDirection(const SurfaceHit& hit, const glm::vec3& w) { return glm::dot(hit.geometricNormal, w) > 0.0f; }

/// Next-event estimation half of estimateDirectLight(): one light chosen by power and one point on it, weighted by
/// MIS against brdfPdf (delta lights unweighted), times f cos / pdf, with an exact shadow ray. wo points away from
/// the surface (toward the previous vertex).
/// shadowRays, when given, is incremented by the number of shadow rays traced (0 or 1). Always draws exactly three
/// random numbers (one for the light, two for the point), whatever the outcome.
/// incident, when given, receives the sample as an IncidentSample (zero weight when it carries nothing).
/// mixed: the other strategy samples directions by LightSampler::mixedScatterPdf() (the reference in media).
glm::vec3 sampleLightDirect(const EmbreeScene& embree, const LightSampler& lights, const SurfaceHit& hit,
                            const glm::vec3& wo, const BrdfParams& brdf, Rng& rng, uint64_t* shadowRays = nullptr,
                            IncidentSample* incident = nullptr, bool mixed = false);

/// BRDF-sampling half: the emitted radiance Le seen at `emitterHit` along wi (unit, from `from` toward the hit),
/// times its MIS weight against sampleLightDirect()'s light pdf. The caller multiplies by f cos / brdfPdf (its path
/// throughput). Zero when the hit is not emissive or is seen from its back.
glm::vec3 misWeightedEmission(const LightSampler& lights, const glm::vec3& from, const SurfaceHit& emitterHit,
                              const glm::vec3& wi, float brdfPdf);

/// Radiance reflected at `hit` toward wo from light arriving straight from the emitters (one reflection):
/// sampleLightDirect() plus one BRDF-sampled ray traced here and counted by misWeightedEmission(). incident, when
/// given, receives both samples (the estimate toward another wo' is sum f(wo', wi) weight: the MIS weights keep the
/// pdfs of wo, so it stays unbiased).
glm::vec3 estimateDirectLight(const EmbreeScene& embree, const LightSampler& lights, const SurfaceHit& hit,
                              const glm::vec3& wo, const BrdfParams& brdf, Rng& rng,
                              std::array<IncidentSample, 2>* incident = nullptr);

class MediumLightSegment;

/// sampleLightDirect() at any path vertex: on a surface exactly the function above; in a medium the phase function
/// replaces f cos (MIS against phase sampling), and the shadow ray starts at the point itself. With media, every
/// shadow ray carries their transmittance. along, for a medium point that a free flight along that segment found:
/// the estimate is weighted by the flight's MIS weight against equiangular sampling toward the drawn light point
/// (medium_direct.h, docs/theory.md §24); the caller adds the segment's equiangular estimate.
glm::vec3 sampleLightDirect(const EmbreeScene& embree, const LightSampler& lights, const Interaction& it, Rng& rng,
                            uint64_t* shadowRays = nullptr, const MediumLightSegment* along = nullptr,
                            bool mixed = false);

/// The medium half of sampleLightDirect() with its three numbers given (the light uLight, the point uPoint): the
/// equiangular technique evaluates it at its own point with the numbers it drew the light point with.
glm::vec3 sampleLightMedium(const EmbreeScene& embree, const LightSampler& lights, const Interaction& it, float uLight,
                            glm::vec2 uPoint, uint64_t* shadowRays, const MediumLightSegment* along,
                            bool mixed = false);

/// estimateDirectLight() at any path vertex (a medium point samples the phase function for the second strategy).
/// Draws 3 + 3 numbers on a surface, 3 + 2 in a medium. along as for sampleLightDirect() (it weights the light-sampling
/// half only: the phase-sampled half stays with the free flight).
glm::vec3 estimateDirectLight(const EmbreeScene& embree, const LightSampler& lights, const Interaction& it, Rng& rng,
                              const MediumLightSegment* along = nullptr);

}  // namespace vplab
