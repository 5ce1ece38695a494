#pragma once
// The point-VPL transfer, written once for every CPU user (rejection importance, the exact VPL renderer, Kollig-Keller
// compensation); shaders mirror it. docs/theory.md §1, §4:
//
//   L(x1 -> wo) += f(x1; wo, w) * G_b(x1, x2) * V(x1, x2) * f(x2; w_in, -w) * Phi
//   w = (x2 - x1) / |x2 - x1|,  G = max(0, n1.w) max(0, n2.(-w)) / |x2 - x1|^2,  G_b = min(G, b)
//
// n1, n2 are shading normals; surfaces are one-sided, so x1 must face the VPL and the VPL must face x1 (geometric
// normals), otherwise the contribution is zero. b = inf gives min(G, inf) = G, bit-identical to no clamp.

#include "renderer/core/brdf.h"
#include "renderer/offline/embree_scene.h"
#include "renderer/offline/interaction.h"
#include "renderer/vpl/vpl.h"

#include <glm/glm.hpp>

#include <algorithm>

namespace vplab {

/// A camera-side surface point being lit: the hit, the direction back toward the viewer and its BRDF.
struct ShadingPoint {
  SurfaceHit hit;
  glm::vec3 wo{0.0f};  ///< unit, away from the surface
  BrdfParams brdf;
};

/// evaluateBrdf() with a shortcut for pure Lambert materials (metallic = specular = 0), where it reduces exactly to
/// baseColor / pi: the common case in the VPL sum, whose cost is dominated by BRDF evaluations besides shadow rays.
inline glm::vec3 evaluateBrdfForVpl(const BrdfParams& p, const glm::vec3& n, const glm::vec3& wo, const glm::vec3& wi) {
  if (p.metallic == 0.0f && p.specular == 0.0f) {
    if (glm::dot(n, wo) <= 0.0f || glm::dot(n, wi) <= 0.0f) return glm::vec3(0.0f);
    return p.baseColor * kInvPi;
  }
  return evaluateBrdf(p, n, wo, wi);
}

/// Where a surface point x1 and a surface VPL x2 can exchange light: w = (x2 - x1) / |x2 - x1|, the shading cosines
/// and G = cos1 cos2 / d^2. False when they cannot (coincident, or either one-sided surface faces away).
struct VplPairGeometry {
  glm::vec3 w{0.0f};
  float cos1 = 0.0f;
  float cos2 = 0.0f;
  float g = 0.0f;
};
inline bool vplPairGeometry(const SurfaceHit& hit, const Vpl& vpl, VplPairGeometry& out) {
  glm::vec3 d = vpl.position - hit.position;
  float dist2 = glm::dot(d, d);
  if (!(dist2 > 0.0f)) return false;
  glm::vec3 w = d * (1.0f / std::sqrt(dist2));
  // One-sided surfaces: both ends must face each other geometrically.
  if (glm::dot(hit.geometricNormal, w) <= 0.0f || glm::dot(vpl.geometricNormal, w) >= 0.0f) return false;
  // Geometry term with cosines clamped at zero (docs/theory.md §1).
  float cos1 = glm::dot(hit.shadingNormal, w);
  float cos2 = -glm::dot(vpl.normal, w);
  if (cos1 <= 0.0f || cos2 <= 0.0f) return false;
  out = {w, cos1, cos2, cos1 * cos2 / dist2};
  return true;
}

/// Unoccluded contribution of one VPL (visibility is the caller's, because shadow rays are batched).
/// `unclamped`, when given, receives the same product with G instead of G_b (for the energy removed by the clamp).
/// `geometryTerm`, when given, receives G (0 when the pair cannot exchange light).
inline glm::vec3 vplUnoccludedContribution(const ShadingPoint& sp, const Vpl& vpl, const BrdfParams& vplBrdf,
                                           float clampBound, glm::vec3* unclamped = nullptr,
                                           float* geometryTerm = nullptr) {
  if (unclamped) *unclamped = glm::vec3(0.0f);
  if (geometryTerm) *geometryTerm = 0.0f;
  VplPairGeometry pair;
  if (!vplPairGeometry(sp.hit, vpl, pair)) return glm::vec3(0.0f);
  const glm::vec3& w = pair.w;
  float g = pair.g;
  // Glossy at both ends: f(x1) from the viewer, f(x2) from the VPL's stored incoming direction.
  glm::vec3 f1 = evaluateBrdfForVpl(sp.brdf, sp.hit.shadingNormal, sp.wo, w);
  glm::vec3 f2 = evaluateBrdfForVpl(vplBrdf, vpl.normal, vpl.incoming, -w);
  glm::vec3 base = f1 * f2 * vpl.flux;
  if (geometryTerm) *geometryTerm = g;
  if (unclamped) *unclamped = base * g;
  // Bounded geometry term G_b = min(G, b) (docs/theory.md §4).
  return base * std::min(g, clampBound);
}

/// The same transfer as light arriving at x1, without x1's BRDF, for re-evaluation toward any viewer: the
/// contribution toward wo is f(x1; wo, wi) * weight, weight = f(x2; w_in, -w) Phi G_b. False when none arrives.
inline bool vplIncident(const SurfaceHit& hit, const Vpl& vpl, const BrdfParams& vplBrdf, float clampBound,
                        IncidentSample& out) {
  VplPairGeometry pair;
  if (!vplPairGeometry(hit, vpl, pair)) return false;
  glm::vec3 f2 = evaluateBrdfForVpl(vplBrdf, vpl.normal, vpl.incoming, -pair.w);
  out = {pair.w, f2 * vpl.flux * std::min(pair.g, clampBound)};
  return out.weight.r > 0.0f || out.weight.g > 0.0f || out.weight.b > 0.0f;
}

/// The transfer of §17 for any pair (docs/theory.md): a receiver on a surface or in a medium, a surface or medium
/// VPL. Unoccluded and without the media's transmittance (the caller's, with the shadow ray):
///   C = [receiver: f(x) cos_x | f_p(x)] * G_b * [VPL: f(y) cos_y | f_p(y)] * Phi,   G = (cosines that exist) / d^2.
/// A medium receiver's sigma_s is not in it (it belongs to the distance integral along the camera ray). vplPhaseG is
/// the medium VPL's Henyey-Greenstein g. A surface receiver and a surface VPL give exactly vplUnoccludedContribution().
inline glm::vec3 vplContributionAt(const Interaction& x, const Vpl& vpl, const BrdfParams& vplBrdf, float vplPhaseG,
                                   float clampBound, glm::vec3* unclamped = nullptr, float* geometryTerm = nullptr) {
  if (!x.inMedium && !vpl.inMedium) {
    ShadingPoint sp{x.hit, x.wo, x.brdf};
    return vplUnoccludedContribution(sp, vpl, vplBrdf, clampBound, unclamped, geometryTerm);
  }
  if (unclamped) *unclamped = glm::vec3(0.0f);
  if (geometryTerm) *geometryTerm = 0.0f;
  glm::vec3 d = vpl.position - x.position;
  float dist2 = glm::dot(d, d);
  if (!(dist2 > 0.0f)) return glm::vec3(0.0f);
  glm::vec3 w = d * (1.0f / std::sqrt(dist2));
  // Receiver end: a one-sided surface's BRDF and cosine, or the phase function (no cosine in a medium).
  float cos1 = 1.0f;
  glm::vec3 f1;
  if (x.inMedium) {
    f1 = glm::vec3(phaseHG(x.wo, w, x.g));
  } else {
    if (glm::dot(x.hit.geometricNormal, w) <= 0.0f) return glm::vec3(0.0f);
    cos1 = glm::dot(x.hit.shadingNormal, w);
    if (cos1 <= 0.0f) return glm::vec3(0.0f);
    f1 = evaluateBrdfForVpl(x.brdf, x.hit.shadingNormal, x.wo, w);
  }
  // VPL end: light leaves the VPL along -w.
  float cos2 = 1.0f;
  glm::vec3 f2;
  if (vpl.inMedium) {
    f2 = glm::vec3(phaseHG(-w, vpl.incoming, vplPhaseG));
  } else {
    if (glm::dot(vpl.geometricNormal, w) >= 0.0f) return glm::vec3(0.0f);
    cos2 = -glm::dot(vpl.normal, w);
    if (cos2 <= 0.0f) return glm::vec3(0.0f);
    f2 = evaluateBrdfForVpl(vplBrdf, vpl.normal, vpl.incoming, -w);
  }
  // The geometric factor without visibility and transmittance, bounded as on surfaces (docs/theory.md §17).
  float g = cos1 * cos2 / dist2;
  glm::vec3 base = f1 * f2 * vpl.flux;
  if (geometryTerm) *geometryTerm = g;
  if (unclamped) *unclamped = base * g;
  return base * std::min(g, clampBound);
}

}  // namespace vplab
