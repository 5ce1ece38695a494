#pragma once
// A path vertex, on a surface or in a medium, behind one interface (as pbrt's Interaction / MediumInteraction), so
// that estimators treat both alike: what it scatters toward wo from a direction wi (the BRDF times the receiver's
// cosine on a surface, the phase function in a medium), how it samples wi and with which pdf, and where rays leaving
// it start. docs/theory.md §16-§17.

#include <cstdint>
#include <glm/glm.hpp>

#include "renderer/core/brdf.h"
#include "renderer/core/sampling.h"
#include "renderer/offline/embree_scene.h"
#include "renderer/scene/brdf_params.h"
#include "renderer/scene/medium.h"
#include "renderer/scene/scene.h"

namespace vplab {

/// One sample of the light arriving at a surface point, kept so that the point's reflection can be re-evaluated
/// toward another viewer: the estimate reflected toward any wo is f(wo, wi) * weight, with the incident radiance, the
/// cosine at the point, 1 / pdf and any MIS weight folded into `weight` (the pdfs those weights use stay the ones the
/// sample was drawn with, so the estimate stays unbiased for every wo where they cover f).
struct IncidentSample {
  glm::vec3 wi{0.0f};
  glm::vec3 weight{0.0f};
};

struct Interaction {
  bool inMedium = false;
  glm::vec3 position{0.0f};
  glm::vec3 wo{0.0f};  ///< unit, toward the viewer (the previous vertex)
  // A surface point:
  SurfaceHit hit;
  BrdfParams brdf;
  // A medium point:
  uint32_t medium = 0;
  float g = 0.0f;
  glm::vec3 sigmaS{0.0f};

  static Interaction onSurface(const Scene& scene, const SurfaceHit& hit, const glm::vec3& wo) {
    Interaction it;
    it.position = hit.position;
    it.wo = wo;
    it.hit = hit;
    it.brdf = brdfParamsAt(scene, hit.material, hit.uv);
    return it;
  }
  static Interaction inMediumAt(const Scene& scene, const glm::vec3& position, uint32_t medium, const glm::vec3& wo) {
    Interaction it;
    it.inMedium = true;
    it.position = position;
    it.wo = wo;
    it.medium = medium;
    it.g = scene.media[medium].g;
    it.sigmaS = scene.media[medium].sigmaSAt(position);
    return it;
  }
  /// The segment at the end of a traced Segment (Surface or Medium), seen from along -wo.
  static Interaction atSegmentEnd(const Scene& scene, const Segment& s, const glm::vec3& wo) {
    return s.scattered() ? inMediumAt(scene, s.position, s.medium, wo) : onSurface(scene, *s.hit, wo);
  }

  /// Surfaces are one-sided: a surface vertex seen from its back scatters nothing. A medium point always scatters.
  bool scatters() const { return inMedium || glm::dot(hit.geometricNormal, wo) > 0.0f; }
  /// True when light arriving from wi can leave toward wo here (the geometric side test of a surface).
  bool accepts(const glm::vec3& wi) const { return inMedium || glm::dot(hit.geometricNormal, wi) > 0.0f; }

  /// The receiver term for light arriving from wi (unit): f(wo, wi) max(0, cos theta_i) on a surface (zero from its
  /// back), the phase function f_p(wo, wi) in a medium. The medium's sigma_s is not in it: it belongs to the
  /// distance integral along the ray that found this point.
  glm::vec3 scatter(const glm::vec3& wi) const {
    if (inMedium) return glm::vec3(phaseHG(wo, wi, g));
    if (!accepts(wi)) return glm::vec3(0.0f);
    float cosI = glm::dot(hit.shadingNormal, wi);
    if (!(cosI > 0.0f)) return glm::vec3(0.0f);
    return evaluateBrdf(brdf, hit.shadingNormal, wo, wi) * cosI;
  }
  /// Solid-angle pdf of sample() drawing wi.
  float pdf(const glm::vec3& wi) const {
    return inMedium ? phaseHG(wo, wi, g) : brdfPdf(brdf, hit.shadingNormal, wo, wi);
  }

  struct Sample {
    glm::vec3 wi{0.0f};
    glm::vec3 f{0.0f};       ///< the BRDF (without the cosine) or the phase function at wi
    glm::vec3 weight{0.0f};  ///< scatter(wi) / pdf
    float pdf = 0.0f;
    bool valid() const { return pdf > 0.0f; }
  };
  /// Draws wi from the BRDF (three numbers) or the phase function (two numbers); invalid when the BRDF sample leaves
  /// through the back of the surface or below the shading normal's horizon.
  template <class Random>
  Sample sample(Random& rng) const {
    Sample s;
    if (inMedium) {
      glm::vec2 u = rng.next2D();
      PhaseSample ps = samplePhaseHG(wo, g, u);
      s.wi = ps.wi;
      s.pdf = ps.pdf;
      s.f = glm::vec3(ps.pdf);
      s.weight = glm::vec3(1.0f);  // f_p / pdf, sampled exactly
      return s;
    }
    glm::vec3 u(rng.next1D(), rng.next1D(), rng.next1D());
    BrdfSample bs = sampleBrdf(brdf, hit.shadingNormal, wo, u);
    if (!bs.valid() || !accepts(bs.wi)) return s;
    float cosI = glm::dot(hit.shadingNormal, bs.wi);
    if (cosI <= 0.0f) return s;
    s.wi = bs.wi;
    s.pdf = bs.pdf;
    s.f = bs.f;
    s.weight = bs.f * (cosI / bs.pdf);
    return s;
  }

  /// Origin of a ray leaving toward dir: a surface point nudged off its surface, a medium point itself.
  glm::vec3 rayOrigin(const EmbreeScene& embree, const glm::vec3& dir) const {
    return inMedium ? position : embree.offsetOrigin(position, hit.geometricNormal, dir);
  }
  /// Normal to pass to EmbreeScene::shadowRayBetween (zero in a medium: no offset).
  glm::vec3 offsetNormal() const { return inMedium ? glm::vec3(0.0f) : hit.geometricNormal; }
};

}  // namespace vplab
