// Mirror of renderer/core/brdf.h evaluateBrdf(): glTF metallic-roughness as Lambert + GGX (height-correlated Smith),
// same constants (F0 0.04, kMinGgxAlpha 1e-3, alpha = roughness^2), both cosines clamped at zero.
#include "common/math.glsl"

const float kMinGgxAlpha = 1e-3;

struct BrdfParams {
  vec3 baseColor;
  float metallic;
  float roughness;
  float specular;
};

float brdfSchlickWeight(float cosTheta) {
  float m = clamp(1.0 - cosTheta, 0.0, 1.0);
  float m2 = m * m;
  return m2 * m2 * m;
}

float brdfGgxD(float cosH, float alpha) {
  float a2 = alpha * alpha;
  float d = cosH * cosH * (a2 - 1.0) + 1.0;
  return a2 / (kPi * d * d);
}

float brdfSmithVisibility(float cosO, float cosI, float alpha) {
  float a2 = alpha * alpha;
  float lo = cosI * sqrt(cosO * cosO * (1.0 - a2) + a2);
  float li = cosO * sqrt(cosI * cosI * (1.0 - a2) + a2);
  float denom = lo + li;
  return denom > 0.0 ? 0.5 / denom : 0.0;
}

// f(wo, wi) at a point with unit normal n; wo and wi point away from the surface. The diffuse lobe is weighted by
// the Fresnel transmission at both ends, (1 - s F_d(cos_o)) (1 - s F_d(cos_i)), exactly as brdf.h does. Written
// without branches: llvmpipe runs both sides of a branch under a lane mask, and the bookkeeping of the early returns
// cost more than the terms they skip. For a pure Lambert material (metallic 0, specular 0) the terms reduce to
// baseColor / pi exactly (factors of 1 and a finite GGX lobe times 0).
vec3 evaluateBrdf(BrdfParams p, vec3 n, vec3 wo, vec3 wi) {
  float cosO = dot(n, wo), cosI = dot(n, wi);
#ifdef BRDF_LAMBERT_ONLY
  // Defined by the renderer when every material of the scene is pure Lambert: the GGX terms would contribute exactly 0.
  return cosO > 0.0 && cosI > 0.0 ? p.baseColor * kInvPi : vec3(0.0);
#else
  vec3 h = wo + wi;
  float hl2 = dot(h, h);
  h *= inversesqrt(max(hl2, 1e-30));
  float vDotH = max(0.0, dot(wo, h));
  float fw = brdfSchlickWeight(vDotH);
  float dielectricF = 0.04 + 0.96 * fw;
  vec3 metalF = p.baseColor + (1.0 - p.baseColor) * fw;
  float alpha = max(kMinGgxAlpha, p.roughness * p.roughness);
  float spec = brdfGgxD(max(0.0, dot(n, h)), alpha) * brdfSmithVisibility(max(cosO, 0.0), max(cosI, 0.0), alpha);
  float transmitO = 1.0 - p.specular * (0.04 + 0.96 * brdfSchlickWeight(cosO));
  float transmitI = 1.0 - p.specular * (0.04 + 0.96 * brdfSchlickWeight(cosI));
  vec3 diffuse = (1.0 - p.metallic) * transmitO * transmitI * p.baseColor * kInvPi;
  vec3 value = diffuse + spec * ((1.0 - p.metallic) * p.specular * dielectricF + p.metallic * metalF);
  return cosO > 0.0 && cosI > 0.0 && hl2 > 0.0 ? value : vec3(0.0);
#endif
}
