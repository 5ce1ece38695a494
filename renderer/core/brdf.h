#pragma once
// The one BRDF of vplab: glTF 2.0 metallic-roughness reduced to a Lambert lobe and a GGX lobe (glTF 2.0 spec,
// Appendix B). Evaluation, sampling and pdf live here and nowhere else on the CPU; shaders/common/brdf.glsl mirrors
// evaluate() with the same constants.
//
//   f = (1 - metallic) (1 - s F_d(cos_o)) (1 - s F_d(cos_i)) baseColor / pi
//       + D G2/(4 cos_o cos_i) [(1 - metallic) s F_d(v.h) + metallic F_m(v.h)]
//   F_d(c) = 0.04 + 0.96 (1 - c)^5         (dielectric, ior 1.5)
//   s   = KHR_materials_specular specularFactor (default 1; 0 makes a dielectric exactly Lambertian, which the
//         measured Cornell reflectances and the furnace need)
//   F_m(c) = baseColor + (1 - baseColor)(1 - c)^5   (conductor)
// The diffuse weight differs from glTF's fresnel_mix (1 - F(v.h)): that per-microfacet weight lets a white dielectric
// reflect up to 1.8x what it receives at grazing angles. Weighting by the Fresnel transmission at both ends
// (Shirley et al. 1997) stays reciprocal and conserves energy (white furnace <= 1, tests/brdf_test.cpp).
// D: GGX/Trowbridge-Reitz with alpha = roughness^2; G2: height-correlated Smith. Both cosines are clamped at zero:
// surfaces reflect only on the side their normal faces.

#include "renderer/core/sampling.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

namespace vplab {

/// Smallest GGX alpha: below this D becomes a spike that float precision cannot evaluate.
inline constexpr float kMinGgxAlpha = 1e-3f;

/// BRDF parameters at one surface point (material factors already multiplied by textures).
struct BrdfParams {
  glm::vec3 baseColor{1.0f};
  float metallic = 0.0f;
  float roughness = 1.0f;
  float specular = 1.0f;

  float alpha() const { return std::max(kMinGgxAlpha, roughness * roughness); }
};

struct BrdfSample {
  glm::vec3 wi{0.0f};   ///< world-space direction toward the next vertex
  glm::vec3 f{0.0f};    ///< BRDF value f(wo, wi)
  float pdf = 0.0f;     ///< solid-angle pdf of wi (mixture of both lobes)
  bool valid() const { return pdf > 0.0f; }
};

namespace brdf_detail {

inline float schlickWeight(float cosTheta) {
  float m = std::clamp(1.0f - cosTheta, 0.0f, 1.0f);
  float m2 = m * m;
  return m2 * m2 * m;
}

inline float ggxD(float cosH, float alpha) {
  float a2 = alpha * alpha;
  float d = cosH * cosH * (a2 - 1.0f) + 1.0f;
  return a2 / (kPi * d * d);
}

/// Height-correlated Smith visibility term V = G2 / (4 cos_o cos_i).
inline float smithVisibility(float cosO, float cosI, float alpha) {
  float a2 = alpha * alpha;
  float lo = cosI * std::sqrt(cosO * cosO * (1.0f - a2) + a2);
  float li = cosO * std::sqrt(cosI * cosI * (1.0f - a2) + a2);
  float denom = lo + li;
  return denom > 0.0f ? 0.5f / denom : 0.0f;
}

/// Smith G1 for the visible-normal pdf.
inline float smithG1(float cosV, float alpha) {
  float a2 = alpha * alpha;
  return 2.0f * cosV / (cosV + std::sqrt(a2 + (1.0f - a2) * cosV * cosV));
}

/// Probability of sampling the specular lobe, from the lobe weights seen from wo.
inline float specularProbability(const BrdfParams& p, float cosO) {
  float fw = schlickWeight(cosO);
  float dielectricF = 0.04f + 0.96f * fw;
  glm::vec3 metalF = p.baseColor + (1.0f - p.baseColor) * fw;
  float spec = (1.0f - p.metallic) * p.specular * dielectricF + p.metallic * luminance(metalF);
  float diff = (1.0f - p.metallic) * (1.0f - p.specular * dielectricF) * luminance(p.baseColor);
  if (!(spec > 0.0f)) return 0.0f;
  if (!(diff > 0.0f)) return 1.0f;
  // Keep both lobes reachable so that the pdf stays well defined wherever f is non-zero.
  return std::clamp(spec / (spec + diff), 0.1f, 0.9f);
}

/// Visible-normal sampling (Heitz 2018, "Sampling the GGX Distribution of Visible Normals"), local frame.
inline glm::vec3 sampleGgxVisibleNormal(const glm::vec3& wo, float alpha, glm::vec2 u) {
  glm::vec3 vh = glm::normalize(glm::vec3(alpha * wo.x, alpha * wo.y, wo.z));
  float lensq = vh.x * vh.x + vh.y * vh.y;
  glm::vec3 t1 = lensq > 0.0f ? glm::vec3(-vh.y, vh.x, 0.0f) / std::sqrt(lensq) : glm::vec3(1.0f, 0.0f, 0.0f);
  glm::vec3 t2 = glm::cross(vh, t1);
  float r = std::sqrt(u.x);
  float phi = 2.0f * kPi * u.y;
  float p1 = r * std::cos(phi);
  float p2 = r * std::sin(phi);
  float s = 0.5f * (1.0f + vh.z);
  p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * p2;
  glm::vec3 nh = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2)) * vh;
  return glm::normalize(glm::vec3(alpha * nh.x, alpha * nh.y, std::max(1e-6f, nh.z)));
}

}  // namespace brdf_detail

/// f(wo, wi) at a point with unit normal n; wo and wi point away from the surface.
inline glm::vec3 evaluateBrdf(const BrdfParams& p, const glm::vec3& n, const glm::vec3& wo, const glm::vec3& wi) {
  using namespace brdf_detail;
  float cosO = glm::dot(n, wo), cosI = glm::dot(n, wi);
  if (cosO <= 0.0f || cosI <= 0.0f) return glm::vec3(0.0f);
  // Pure Lambert (the measured Cornell and furnace materials): skip the GGX terms, which would contribute exactly 0.
  if (p.metallic <= 0.0f && p.specular <= 0.0f) return p.baseColor * kInvPi;
  glm::vec3 h = wo + wi;
  float hl = glm::length(h);
  if (!(hl > 0.0f)) return glm::vec3(0.0f);
  h /= hl;
  float vDotH = std::max(0.0f, glm::dot(wo, h));
  float fw = schlickWeight(vDotH);
  float dielectricF = 0.04f + 0.96f * fw;
  glm::vec3 metalF = p.baseColor + (1.0f - p.baseColor) * fw;
  float alpha = p.alpha();
  float specular = ggxD(std::max(0.0f, glm::dot(n, h)), alpha) * smithVisibility(cosO, cosI, alpha);
  float transmitO = 1.0f - p.specular * (0.04f + 0.96f * schlickWeight(cosO));
  float transmitI = 1.0f - p.specular * (0.04f + 0.96f * schlickWeight(cosI));
  glm::vec3 diffuse = (1.0f - p.metallic) * transmitO * transmitI * p.baseColor * kInvPi;
  return diffuse + specular * ((1.0f - p.metallic) * p.specular * dielectricF + p.metallic * metalF);
}

/// Solid-angle pdf with which sampleBrdf() produces wi.
inline float brdfPdf(const BrdfParams& p, const glm::vec3& n, const glm::vec3& wo, const glm::vec3& wi) {
  using namespace brdf_detail;
  float cosO = glm::dot(n, wo), cosI = glm::dot(n, wi);
  if (cosO <= 0.0f || cosI <= 0.0f) return 0.0f;
  glm::vec3 h = glm::normalize(wo + wi);
  float alpha = p.alpha();
  float pSpec = specularProbability(p, cosO);
  if (pSpec <= 0.0f) return cosI * kInvPi;
  // Visible-normal pdf: D_v(h) / (4 wo.h) with D_v = G1(wo) max(0, wo.h) D(h) / cos_o.
  float specPdf = smithG1(cosO, alpha) * ggxD(std::max(0.0f, glm::dot(n, h)), alpha) / (4.0f * cosO);
  return pSpec * specPdf + (1.0f - pSpec) * cosI * kInvPi;
}

/// Samples wi from the lobe mixture. u.x picks the lobe (and is re-used), u.yz the direction.
inline BrdfSample sampleBrdf(const BrdfParams& p, const glm::vec3& n, const glm::vec3& wo, glm::vec3 u) {
  using namespace brdf_detail;
  BrdfSample s;
  float cosO = glm::dot(n, wo);
  if (cosO <= 0.0f) return s;
  Frame frame(n);
  float pSpec = specularProbability(p, cosO);
  if (pSpec <= 0.0f) {
    // Diffuse only: f cos / pdf needs no general evaluation.
    glm::vec3 local = sampleCosineHemisphere({u.y, u.z});
    if (!(local.z > 0.0f)) return s;
    s.wi = glm::normalize(frame.toWorld(local));
    float cosI = glm::dot(n, s.wi);
    if (cosI <= 0.0f) return s;
    s.pdf = cosI * kInvPi;
    s.f = evaluateBrdf(p, n, wo, s.wi);
    return s;
  }
  if (u.x < pSpec) {
    glm::vec3 woLocal = frame.toLocal(wo);
    glm::vec3 h = sampleGgxVisibleNormal(woLocal, p.alpha(), {u.y, u.z});
    glm::vec3 wiLocal = glm::reflect(-woLocal, h);
    if (wiLocal.z <= 0.0f) return s;
    s.wi = frame.toWorld(wiLocal);
  } else {
    s.wi = frame.toWorld(sampleCosineHemisphere({u.y, u.z}));
  }
  s.wi = glm::normalize(s.wi);
  s.pdf = brdfPdf(p, n, wo, s.wi);
  s.f = evaluateBrdf(p, n, wo, s.wi);
  if (!(s.pdf > 0.0f) || !std::isfinite(s.pdf)) s = BrdfSample{};
  return s;
}

}  // namespace vplab
