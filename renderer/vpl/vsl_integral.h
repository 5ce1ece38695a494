#pragma once
// The virtual-spherical-light transfer (Hasan et al. 2009; docs/methods.md, "r — virtual spherical lights"):
//
//   T = 1 / (pi r^2) * integral over Omega of f(x1; wo, w) f(x2; w_in, -w) cos1+ cos2+ dw,   contribution = Phi T V
//
// Omega is the cone from x1 subtended by the sphere (centre x2, radius r); the whole sphere of directions when
// |x2 - x1| <= r. cos1+ = max(0, n1.w), cos2+ = max(0, -n2.w), and w must leave x1 on its front side and reach x2 on
// the VPL's front side (geometric normals). This file holds the pieces both passes share:
//   - vslCone(): the cone, with 1 - cos(theta_max) and Omega / (pi r^2) free of cancellation for tiny r;
//   - vslLambertCone(): the exact integral of cos1+ cos2+ over an unclipped cone (closed form), and the centre +
//     ring quadrature the approximation uses for every cone;
//   - vslApproxTransfer(): the deterministic approximation of T the GL preview evaluates (mirrored line by line in
//     shaders/common/vsl.glsl), and which the CPU pass uses for pure-Lambert pairs whose cone is unclipped, where it
//     is exact.
//
// The approximation (docs/methods.md gives its measured error). Split f = d + s into its diffuse part d (smooth in w)
// and its GGX part s (a lobe that may be narrower than the cone):
//   T ~ Omega / (pi r^2) * [ d1 d2 <c1 c2> + d2 <s1 c1> <c1 c2> / <c1> + d1 <s2 c2> <c1 c2> / <c2>
//                             + <s1 c1> <s2 c2> <c1 c2> / (<c1> <c2>) ]
// <.> is the mean over the cone, c1 = cos1+, c2 = cos2+ (with the one-sided tests); d1, d2 are taken at the cone
// axis a (the direction to the centre). A lobe's smooth partner is the other end's cosine weighted by the lobe
// end's cosine, which carries the other horizon's clipping; for a small unclipped cone every ratio is 1.
//   <c1 c2>: cos1+ cos2+ (with the geometric-normal tests) by a centre + ring rule: weight 1/4 at a and 3/4 spread
//     over kVslRingNodes directions at cos(theta) = (1 + 2 cos(theta_max)) / 3. The rule integrates every quadratic
//     polynomial in w over the cone exactly, so an unclipped cone (all four planes below it) is exact; a cone that
//     the receiver's or the VPL's horizon cuts is approximated, and its integrand is continuous (it vanishes at the
//     horizon), so the error has no steps. Inside the sphere the closed form over the whole sphere is used,
//     integral of max(0, a.w) max(0, b.w) = 2/3 ((pi - g) cos g + sin g), g = angle(a, b).
//   <s c>: the GGX lobe averaged over the cone. With h the half vector and D dw_h = P22(m) dm / cos(theta_h) (P22
//     the slope distribution alpha^2 / (pi (alpha^2 + |m|^2)^2)), the cone maps to a region of the slope plane of
//     area Omega / (4 (wo.h) cos^3 theta_h) around m(h_a). Replacing that region by the disk of equal area, the mass
//     of P22 over it is the point-to-parallel-disk form factor from height alpha,
//       P = 1/2 [1 - (alpha^2 + s^2 - rho^2) / sqrt(((s - rho)^2 + alpha^2)((s + rho)^2 + alpha^2))],
//     s = tan(theta_h), rho the disk's radius, and <s c> = V(cos_o, cos_i) F(wo.h) cos_i * 4 (wo.h) / cos(theta_h)
//     * P / Omega, with Smith V and Fresnel F at the axis. For a cone small against the lobe this is the point value
//     D V F cos_i; for a lobe inside the cone it is the lobe's whole mass; in between it widens the highlight the way
//     the convolution does (exact at the lobe's peak).
//   As r -> 0 every mean tends to the value at the axis and Omega / (pi r^2) -> 1 / d^2: T tends to the point VPL.

#include "renderer/core/brdf.h"
#include "renderer/core/sampling.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

namespace vplab {

/// Ring directions of the centre + ring rule for <cos1+ cos2+> (vsl_integral.h; vsl.glsl uses the same count).
inline constexpr int kVslRingNodes = 6;

/// The cone a sphere (radius r) subtends from x1; the whole sphere of directions when x1 lies inside it.
struct VslCone {
  glm::vec3 axis{0.0f, 0.0f, 1.0f};  ///< unit direction x1 -> centre
  float cosThetaMax = 1.0f;          ///< -1 inside the sphere
  float sinThetaMax = 0.0f;          ///< r / d; 0 inside the sphere
  float oneMinusCos = 0.0f;          ///< 1 - cosThetaMax without cancellation (2 inside)
  float solidAngle = 0.0f;           ///< Omega = 2 pi (1 - cos theta_max)
  float solidAngleOverArea = 0.0f;   ///< Omega / (pi r^2); 1 / d^2 as r -> 0
  bool inside = false;
};

/// toCentre = x2 - x1 (non-zero unless inside), radius >= 0; fallbackAxis is the axis when x1 is the centre.
inline VslCone vslCone(const glm::vec3& toCentre, float radius, const glm::vec3& fallbackAxis) {
  VslCone c;
  float dist2 = glm::dot(toCentre, toCentre);
  float r2 = radius * radius;
  float invDist2 = 1.0f / std::max(dist2, 1e-30f), invDist = std::sqrt(invDist2);
  c.axis = dist2 > 0.0f ? toCentre * invDist : fallbackAxis;
  if (dist2 <= r2) {
    c.inside = true;
    c.cosThetaMax = -1.0f;
    c.sinThetaMax = 0.0f;
    c.oneMinusCos = 2.0f;
    c.solidAngle = 4.0f * kPi;
    c.solidAngleOverArea = 4.0f / r2;
    return c;
  }
  float s2 = r2 * invDist2;  // sin^2 theta_max
  float root = std::sqrt(std::max(0.0f, 1.0f - s2));
  float invOnePlusRoot = 1.0f / (1.0f + root);
  c.cosThetaMax = root;
  c.sinThetaMax = radius * invDist;
  c.oneMinusCos = s2 * invOnePlusRoot;
  c.solidAngle = 2.0f * kPi * c.oneMinusCos;
  c.solidAngleOverArea = 2.0f * invDist2 * invOnePlusRoot;
  return c;
}

/// Whether the cone lies entirely on the positive side of the plane with unit normal `normal` through x1, with
/// offset = normal . (x2 - x1): the sphere is above the plane by more than its radius.
inline bool vslConeAbovePlane(float offset, float radius) { return offset > radius; }

/// Means over the cone of cos1+ cos2+, cos1+ and cos2+ (all three with the one-sided tests).
struct VslCosineMeans {
  float product = 0.0f;
  float cos1 = 0.0f;
  float cos2 = 0.0f;
};

/// The means for cos1 = n1.w, cos2 = m2.w (m2 = -n2), with the one-sided tests g1.w > 0 and g2.w > 0 (g1 = receiver
/// geometric normal, g2 = -VPL geometric normal). Centre + ring rule (see the top of this file); inside the sphere
/// the closed forms over the whole sphere (geometric tests folded into the shading normals): with g = angle(n1, m2),
///   integral of max(0, n1.w) max(0, m2.w) = 2/3 ((pi - g) cos g + sin g),
///   integral of max(0, n1.w) [m2.w > 0] = pi (1 + cos g) / 2   (the projected area of a quarter sphere).
inline VslCosineMeans vslCosineMeans(const VslCone& cone, const glm::vec3& n1, const glm::vec3& g1,
                                     const glm::vec3& m2, const glm::vec3& g2) {
  VslCosineMeans m;
  if (cone.inside) {
    float cosG = std::clamp(glm::dot(n1, m2), -1.0f, 1.0f);
    float g = std::acos(cosG);
    m.product = (2.0f / 3.0f) * ((kPi - g) * cosG + std::sqrt(std::max(0.0f, 1.0f - cosG * cosG))) / cone.solidAngle;
    m.cos1 = m.cos2 = 0.125f * (1.0f + cosG);
    return m;
  }
  Frame f(cone.axis);
  // The four normals' components in the cone's frame, one vector per axis (n1, g1, m2, g2): a node's four dot
  // products are then z * Z + x * X + y * Y, and the ring's opposite nodes k and k + 3 share z * Z and differ in the
  // sign of the rest.
  const glm::vec3 l1 = f.toLocal(n1), lg1 = f.toLocal(g1), l2 = f.toLocal(m2), lg2 = f.toLocal(g2);
  const glm::vec4 X(l1.x, lg1.x, l2.x, lg2.x), Y(l1.y, lg1.y, l2.y, lg2.y), Z(l1.z, lg1.z, l2.z, lg2.z);
  auto add = [&m](float weight, const glm::vec4& dots) {
    if (!(dots.y > 0.0f && dots.w > 0.0f)) return;
    float c1 = std::max(0.0f, dots.x), c2 = std::max(0.0f, dots.z);
    m.product += weight * c1 * c2;
    m.cos1 += weight * c1;
    m.cos2 += weight * c2;
  };
  float z = 1.0f - 2.0f * cone.oneMinusCos / 3.0f;  // (1 + 2 cos theta_max) / 3
  float sinT = std::sqrt(std::max(0.0f, (2.0f * cone.oneMinusCos / 3.0f) * (1.0f + z)));
  // Nodes at 2 pi k / 6: (cos, sin) = (1, 0), (1/2, sqrt(3)/2), (-1/2, sqrt(3)/2) and their opposites.
  const glm::vec4 zc = z * Z, p0 = sinT * X, p1 = sinT * (0.5f * X + 0.8660254f * Y),
                  p2 = sinT * (-0.5f * X + 0.8660254f * Y);
  constexpr float kRingWeight = 0.75f / static_cast<float>(kVslRingNodes);
  add(0.25f, Z);
  for (const glm::vec4& p : {p0, p1, p2}) {
    add(kRingWeight, zc + p);
    add(kRingWeight, zc - p);
  }
  return m;
}

/// The same mean for a cone that no plane cuts, where the integrand is the quadratic (n1.w)(m2.w): from the cone's
/// moments <z^2> = (1 + c + c^2) / 3 (c = cos theta_max) and <x^2> = <y^2> = (1 - <z^2>) / 2, exactly
///   <(n1.w)(m2.w)> = <z^2> c1 c2 + <x^2> (n1.m2 - c1 c2),   c1 = n1.a, c2 = m2.a.
/// The centre + ring rule gives the same value (it is exact for quadratics); this form skips the frame.
inline float vslMeanCosineProductUnclipped(const VslCone& cone, const glm::vec3& n1, const glm::vec3& m2) {
  float c = cone.cosThetaMax;
  float z2 = (1.0f + c + c * c) / 3.0f;
  float c1 = glm::dot(n1, cone.axis), c2 = glm::dot(m2, cone.axis);
  return z2 * c1 * c2 + 0.5f * (1.0f - z2) * (glm::dot(n1, m2) - c1 * c2);
}

/// Mass of the slope distribution P22 (GGX, alpha^2 = a2) over the disk of radius^2 rho2 centred at slope length^2 s2,
/// divided by `solidAngle` (so that it stays finite as the disk and the cone shrink to a point together:
/// rho2PerSolidAngle = rho2 / Omega). The point-to-parallel-disk form factor, written without cancellation.
///   q^2 = ((s - rho)^2 + a2)((s + rho)^2 + a2) = (s^2 - rho^2)^2 + a2 (2 (s^2 + rho^2) + a2)   (no square roots of s
/// and rho, no cancellation), P = (q - (a2 + s^2 - rho^2)) / (2 q); where a2 + s^2 > rho^2 the same as
/// 2 a2 rho^2 / (q (q + a2 + s^2 - rho^2)), since q^2 - (a2 + s^2 - rho^2)^2 = 4 a2 rho^2. One division: the mass is
/// at most 1 (the cap num / max(den, num Omega) only acts on rounding).
inline float ggxDiskMassPerSolidAngle(float a2, float s2, float rho2PerSolidAngle, float solidAngle) {
  float rho2 = rho2PerSolidAngle * solidAngle;
  float diff = s2 - rho2;
  float q = std::sqrt(diff * diff + a2 * (2.0f * (s2 + rho2) + a2));
  float a = a2 + s2;
  bool narrow = a > rho2;
  float num = narrow ? 2.0f * a2 * rho2PerSolidAngle : 0.5f * (q + rho2 - a);
  float den = narrow ? q * (q + a - rho2) : q * solidAngle;
  return num / std::max(den, num * solidAngle);
}

/// A GGX lobe over the cone: its mean, how much of it the cone holds, and where in the cone it peaks.
struct VslLobe {
  glm::vec3 mean{0.0f};        ///< <s cos_i>
  float coverage = 0.0f;       ///< A B / (A B + alpha^2): 0 for a cone small against the lobe, 1 when it holds it
  glm::vec3 peak{0.0f, 0.0f, 1.0f};  ///< the cone direction closest to the mirror direction of wo
};

/// The cone direction (around `axis`, the cone's own or its reverse) closest to the unit direction `dir`, given
/// c = dir . axis and s = sqrt(1 - c^2).
inline glm::vec3 vslClosestInCone(const VslCone& cone, const glm::vec3& axis, const glm::vec3& dir, float c, float s) {
  if (cone.inside || c >= cone.cosThetaMax) return dir;
  if (!(s > 1e-6f)) return axis;
  return axis * cone.cosThetaMax + (dir - c * axis) * (cone.sinThetaMax / s);
}

/// The GGX part of f(n; wo, w) times cos_i over the cone, w around `axis` (see the top of this file); meanCos is the
/// cone mean of this end's cos_i with the one-sided tests (VslCosineMeans), which carries the horizons' clipping.
inline VslLobe vslMeanSpecular(const BrdfParams& p, const glm::vec3& n, const glm::vec3& wo, const glm::vec3& axis,
                               const VslCone& cone, float meanCos) {
  using namespace brdf_detail;
  VslLobe lobe;
  lobe.peak = axis;
  float cosO = glm::dot(n, wo), cosI = glm::dot(n, axis);
  if (cosO <= 0.0f || cosI <= 0.0f || (p.metallic <= 0.0f && p.specular <= 0.0f)) return lobe;
  glm::vec3 h = wo + axis;
  float hl2 = glm::dot(h, h);
  if (!(hl2 > 0.0f)) return lobe;
  h *= 1.0f / std::sqrt(hl2);
  float cosH = glm::dot(n, h);
  if (cosH <= 0.0f) return lobe;
  cosH = std::max(cosH, 1e-6f);
  float vDotH = std::max(1e-6f, glm::dot(wo, h));
  float alpha = p.alpha();
  float cosH2 = cosH * cosH;
  float invCosH = 1.0f / cosH, invVDotH = 1.0f / vDotH;
  float invCosH2 = invCosH * invCosH;
  float tan2 = std::max(0.0f, 1.0f - cosH2) * invCosH2;
  // The cone's image in the slope plane is an ellipse, the circle of solid angle Omega through two linear maps: the
  // half-vector map scales by 1/2 in the plane of wo and w and by 1 / (2 wo.h) across it; the slope map by
  // 1 / cos^2 theta_h radially and 1 / cos theta_h tangentially, at an angle beta to the first pair of axes. Its area
  // is pi A B = det Omega. The lobe's centre lies radially from the ellipse's centre, at s = tan theta_h, so the
  // disk that decides whether the ellipse reaches the lobe is the one of the ellipse's radial extent rho_r,
  //   rho_r^2 = Omega / (4 pi cos^4 theta_h (cos^2 beta + (wo.h)^2 sin^2 beta)),
  // with the area factor A B (rho_r^2 + alpha^2) / (rho_r^2 (A B + alpha^2)) that restores the small-cone limit (area
  // times P22) and tends to 1 for a cone that holds the lobe. cos beta = (cos_o - (wo.h) cos theta_h) /
  // (sin(wo, h) sin theta_h); only its square is needed, so no square roots.
  float det = 0.25f * invVDotH * invCosH2 * invCosH;
  float a2 = alpha * alpha;
  float cosBetaNum = cosO - vDotH * cosH;
  float sin2Prod = std::max(0.0f, 1.0f - vDotH * vDotH) * std::max(0.0f, 1.0f - cosH2);
  float cb2 = sin2Prod > 1e-12f ? std::min(1.0f, cosBetaNum * cosBetaNum / sin2Prod) : 1.0f;
  float radialDenom = 4.0f * kPi * cosH2 * cosH2 * (cb2 + vDotH * vDotH * (1.0f - cb2));
  float radialPerSolidAngle = 1.0f / radialDenom;
  float ab = det * cone.solidAngle / kPi, radial2 = radialPerSolidAngle * cone.solidAngle;
  // A centred ellipse that is long and thin (grazing wo) holds less of a narrow lobe than the disk of equal area:
  // the exact mass of P22 over it, 1 / sqrt((1 + alpha^2 / A^2)(1 + alpha^2 / B^2)), against the disk's
  // 1 / (1 + alpha^2 / (A B)), scales it: (A B + alpha^2) / sqrt(A^2 B^2 + alpha^2 (A^2 + B^2) + alpha^4), with
  // A^2 + B^2 = |L|_F^2 Omega / pi for the combined map L. 1 for a circle and in both limits (tiny or huge cones).
  // Its numerator cancels the area factor's denominator.
  float sr2 = invCosH2 * invCosH2, st2 = invCosH2;                // slope map, squared
  float ti2 = 0.25f, tp2 = 0.25f * invVDotH * invVDotH;            // half-vector map, squared
  float frob2 = (sr2 * ti2 + st2 * tp2) * cb2 + (sr2 * tp2 + st2 * ti2) * (1.0f - cb2);
  float sumSq = frob2 * cone.solidAngle / kPi;
  float mass = ggxDiskMassPerSolidAngle(a2, tan2, radialPerSolidAngle, cone.solidAngle) *
               (det * radialDenom / kPi) * (radial2 + a2) / std::sqrt(ab * ab + a2 * sumSq + a2 * a2);
  // The slope-plane picture linearises the maps at the axis, which fails for wide cones (x1 close to the sphere):
  // bound the mass by what the lobe can put on the cone's side of the line that touches the cone where it is
  // closest to the mirror direction R (the cone is convex: it lies on one side of that line). Near R the slope m of
  // the half vector maps to w linearly, by 2 in the plane of n and wo and by 2 cos_o across it, so the line at the
  // angle delta from R (positive outside the cone) lies at the slope distance t, t^2 = tan^2(delta / 2) / q with
  // q = 1 - sin^2(theta_o) u_perp^2 (u the unit direction from R toward the axis, u_perp its component across the
  // plane; tan(delta / 2) = sin delta / (1 + cos delta) is exact in the plane). P22's mass beyond a line at distance
  // t is 1/2 (1 - t / sqrt(t^2 + alpha^2)); the cone gets at most that when R is outside, 1 minus it when inside.
  // The bound never binds for a small cone (whose mass is O(Omega)). Directions are exact in w, so it holds for
  // wide cones, where a grazing wo makes the lobe narrow across the plane and the disk would hold all of it.
  const glm::vec3 mirror = 2.0f * cosO * n - wo;
  float cosMirror = glm::dot(mirror, axis);
  float sin2Mirror = std::max(0.0f, 1.0f - cosMirror * cosMirror), sinMirror = std::sqrt(sin2Mirror);
  if (!cone.inside) {
    float sinDelta = sinMirror * cone.cosThetaMax - cosMirror * cone.sinThetaMax;
    float onePlusCosDelta = 1.0f + cosMirror * cone.cosThetaMax + sinMirror * cone.sinThetaMax;
    float across = glm::dot(axis, glm::cross(n, wo));  // sin(theta_o) sin(R, axis) u_perp
    float q = 1.0f - std::min(1.0f - cosO * cosO, across * across / std::max(sin2Mirror, 1e-12f));
    float t2 = sinDelta * sinDelta / std::max(onePlusCosDelta * onePlusCosDelta * q, 1e-30f);
    float root = std::sqrt(t2 + a2);
    float beyond = 0.5f * a2 / (root * (root + std::sqrt(t2)));  // 1/2 (1 - t / root) without cancellation
    float bound = sinDelta > 0.0f ? beyond : 1.0f - beyond;
    mass = std::min(mass, bound / std::max(cone.solidAngle, 1e-30f));
  }
  lobe.coverage = ab / (ab + a2);
  lobe.peak = vslClosestInCone(cone, axis, mirror, cosMirror, sinMirror);
  // The smooth factors V F cos_i 4 (wo.h) / cos(theta_h) where the lobe's mass is: at the axis for a cone small
  // against the lobe, at its peak for a cone that holds it. For the small cone, f is smooth over it and the mean of
  // f cos_i is f at the axis times the mean of cos_i, which vanishes where a horizon cuts the cone (a VPL sphere
  // that reaches below a glossy floor): so cos_i there is meanCos, not its value at the axis.
  glm::vec3 we = glm::normalize(axis + lobe.coverage * (lobe.peak - axis));
  glm::vec3 he = glm::normalize(wo + we);
  float cosIe = std::max(0.0f, glm::dot(n, we)), cosHe = std::max(1e-6f, glm::dot(n, he));
  float vDotHe = std::max(1e-6f, glm::dot(wo, he));
  float fw = schlickWeight(vDotHe);
  glm::vec3 weight = (1.0f - p.metallic) * p.specular * (0.04f + 0.96f * fw) +
                     p.metallic * (p.baseColor + (1.0f - p.baseColor) * fw);
  float cosMean = meanCos + lobe.coverage * (cosIe - meanCos);
  lobe.mean = weight * (smithVisibility(cosO, cosIe, alpha) * cosMean * 4.0f * vDotHe / cosHe * mass);
  return lobe;
}

/// The diffuse part of f (brdf.h) toward wi, with the Fresnel transmission at cos_i clamped to [0, 1].
inline glm::vec3 diffuseBrdf(const BrdfParams& p, const glm::vec3& n, const glm::vec3& wo, const glm::vec3& wi) {
  using namespace brdf_detail;
  float cosO = glm::dot(n, wo);
  if (cosO <= 0.0f) return glm::vec3(0.0f);
  float transmitO = 1.0f - p.specular * (0.04f + 0.96f * schlickWeight(cosO));
  float transmitI = 1.0f - p.specular * (0.04f + 0.96f * schlickWeight(std::max(0.0f, glm::dot(n, wi))));
  return (1.0f - p.metallic) * transmitO * transmitI * p.baseColor * kInvPi;
}

/// One end of a VSL exchange: position, shading and geometric normal, the direction f is seen from, the BRDF.
struct VslEnd {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f, 0.0f, 1.0f};
  glm::vec3 geometricNormal{0.0f, 0.0f, 1.0f};
  glm::vec3 wo{0.0f, 0.0f, 1.0f};  ///< receiver: toward the viewer; VPL: toward where its light came from
  BrdfParams brdf;
};

/// Deterministic approximation of T (the top of this file); radius 0 gives the unclamped point VPL.
inline glm::vec3 vslApproxTransfer(const VslEnd& x1, const VslEnd& x2, float radius) {
  glm::vec3 d = x2.position - x1.position;
  if (!(glm::dot(d, d) > 0.0f) && !(radius > 0.0f)) return glm::vec3(0.0f);
  VslCone cone = vslCone(d, radius, x1.normal);
  const glm::vec3 a = cone.axis;
  VslCosineMeans c = vslCosineMeans(cone, x1.normal, x1.geometricNormal, -x2.normal, -x2.geometricNormal);
  glm::vec3 d1 = diffuseBrdf(x1.brdf, x1.normal, x1.wo, a), d2 = diffuseBrdf(x2.brdf, x2.normal, x2.wo, -a);
  VslLobe s1 = vslMeanSpecular(x1.brdf, x1.normal, x1.wo, a, cone, c.cos1);
  VslLobe s2 = vslMeanSpecular(x2.brdf, x2.normal, x2.wo, -a, cone, c.cos2);
  glm::vec3 mean = d1 * d2 * c.product;
  if (c.product > 0.0f) {
    // A lobe's smooth partner is the other end's cosine: for a cone small against the lobe its mean weighted by the
    // lobe end's cosine, <c1 c2> / <c1> (which carries the other horizon's clipping and the geometric tests); for a
    // cone that holds the lobe, its value where the lobe peaks. Blended by the lobe's coverage.
    auto facing = [&](const glm::vec3& w) {
      return glm::dot(x1.geometricNormal, w) > 0.0f && glm::dot(x2.geometricNormal, w) < 0.0f;
    };
    const glm::vec3 w1 = s1.peak, w2 = -s2.peak;
    float atPeak1 = facing(w1) ? std::max(0.0f, -glm::dot(x2.normal, w1)) : 0.0f;
    float atPeak2 = facing(w2) ? std::max(0.0f, glm::dot(x1.normal, w2)) : 0.0f;
    float productOverBoth = c.product / std::max(c.cos1 * c.cos2, 1e-30f);  // <c1 c2> / (<c1> <c2>)
    float mean1 = productOverBoth * c.cos2, mean2 = productOverBoth * c.cos1;  // <c1 c2> / <c1>, <c1 c2> / <c2>
    float partner1 = mean1 + s1.coverage * (atPeak1 - mean1), partner2 = mean2 + s2.coverage * (atPeak2 - mean2);
    mean += d2 * s1.mean * partner1 + d1 * s2.mean * partner2 + s1.mean * s2.mean * productOverBoth;
  }
  return mean * cone.solidAngleOverArea;
}

/// Whether a pair's cone lies above all four planes (both shading and both geometric normals). For a pure-Lambert
/// pair, vslLambertTransfer() is then the exact integral and the CPU pass needs no cone samples.
inline bool vslConeUnclipped(const VslEnd& x1, const VslEnd& x2, float radius) {
  glm::vec3 d = x2.position - x1.position;
  return glm::dot(d, d) > radius * radius && vslConeAbovePlane(glm::dot(x1.normal, d), radius) &&
         vslConeAbovePlane(glm::dot(x1.geometricNormal, d), radius) &&
         vslConeAbovePlane(-glm::dot(x2.normal, d), radius) &&
         vslConeAbovePlane(-glm::dot(x2.geometricNormal, d), radius);
}

inline bool isPureLambert(const BrdfParams& p) { return p.metallic <= 0.0f && p.specular <= 0.0f; }

/// T for a pure-Lambert pair with an unclipped cone (vslConeUnclipped()): exact.
inline glm::vec3 vslLambertTransfer(const VslEnd& x1, const VslEnd& x2, float radius) {
  VslCone cone = vslCone(x2.position - x1.position, radius, x1.normal);
  return x1.brdf.baseColor * x2.brdf.baseColor *
         (kInvPi * kInvPi * vslMeanCosineProductUnclipped(cone, x1.normal, -x2.normal) * cone.solidAngleOverArea);
}

/// T by brute force: the midpoint rule on an n x n grid of the cone in (cos theta, phi), i.e. n^2 directions of
/// equal solid angle. The reference the approximation is measured against (tests, bench/vsl_bench.cpp); n = 256
/// resolves GGX lobes down to alpha ~ 0.01 in cones of a few degrees.
inline glm::vec3 vslTransferNumerical(const VslEnd& x1, const VslEnd& x2, float radius, int n) {
  VslCone cone = vslCone(x2.position - x1.position, radius, x1.normal);
  Frame frame(cone.axis);
  glm::vec3 sum(0.0f);
  for (int i = 0; i < n; ++i) {
    // z = 1 - t (1 - c) with t in (0, 1): written from oneMinusCos so that tiny cones keep their precision.
    float t = (static_cast<float>(i) + 0.5f) / static_cast<float>(n);
    float oneMinusZ = t * cone.oneMinusCos;
    float z = 1.0f - oneMinusZ, sinTheta = std::sqrt(std::max(0.0f, oneMinusZ * (2.0f - oneMinusZ)));
    for (int j = 0; j < n; ++j) {
      float phi = 2.0f * kPi * (static_cast<float>(j) + 0.5f) / static_cast<float>(n);
      glm::vec3 w = frame.toWorld({sinTheta * std::cos(phi), sinTheta * std::sin(phi), z});
      if (glm::dot(x1.geometricNormal, w) <= 0.0f || glm::dot(x2.geometricNormal, w) >= 0.0f) continue;
      float cos1 = glm::dot(x1.normal, w), cos2 = -glm::dot(x2.normal, w);
      if (cos1 <= 0.0f || cos2 <= 0.0f) continue;
      sum += evaluateBrdf(x1.brdf, x1.normal, x1.wo, w) * evaluateBrdf(x2.brdf, x2.normal, x2.wo, -w) * (cos1 * cos2);
    }
  }
  return sum * (cone.solidAngleOverArea / static_cast<float>(n * n));
}

}  // namespace vplab
