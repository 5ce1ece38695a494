#pragma once
// The error bound of a light-tree node at a receiver (Walter et al. 2005 §4.2, with the bound b and a GGX receiver;
// docs/methods.md "Lightcuts"). For every VPL y of the node, with w the unit direction from x1 to y,
//   f(x1; wo, w) min(G(x1, y), b) s_y(w) <= B,   s_y = f(y; w_in, -w) Phi_y / I_y in [0, 1] (light_tree.h),
// so the node's true contribution and its representative's estimate both lie in [0, B I_C] per channel, and B I_C
// bounds the error of replacing the one by the other (V <= 1). B is built from
//   - d_min: the distance from x1 to the node's box (0 inside it),
//   - the cone of directions from x1 holding the box's bounding sphere (half-angle theta_b; every direction when x1
//     is inside the sphere),
//   - cos1 <= cos(max(0, angle(n1, cone axis) - theta_b)),
//   - cos2 <= cos(max(0, angle(node cone axis, -cone axis) - theta_n - theta_b)) (theta_n: the node's normal cone),
//   - G_b <= min(b, cos1 cos2 / d_min^2): the bound b keeps B finite when x1 is in or near the box, so clamping
//     makes cuts smaller,
//   - f(x1): Lambert baseColor / pi; the GGX lobe through D(theta_h) with theta_h >= max(0, angle(w, w_r)) / 2 for
//     the mirror direction w_r of wo (a reflection about h composed with one about n is a rotation by twice their
//     angle, so |angle(w, w_r)| <= 2 angle(h, n)), D decreasing in theta_h; Fresnel <= 1; the Smith visibility
//     V <= 1 / (2 alpha cos_o), and V cos1 <= c / (2 cos_o sqrt(c^2 (1 - alpha^2) + alpha^2)) with c the bound on
//     cos1 (increasing in c). With the bound b the GGX lobe enters as min(f cos1 cos2 / d_min^2, f b).
// All bounds take the maximum over the RGB channels of f(x1).

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>

#include "renderer/core/brdf.h"
#include "renderer/offline/light_tree.h"
#include "renderer/vpl/vpl_contribution.h"

namespace vplab {

namespace lightcut_detail {

/// The largest cosine between a unit vector and the directions of a cone: cosAngle is the cosine of the angle between
/// the vector and the cone's axis, (cosHalf, sinHalf) the cone's half-angle. 1 when the vector is inside the cone.
inline float cosMaxWithinCone(float cosAngle, float cosHalf, float sinHalf) {
  cosAngle = std::clamp(cosAngle, -1.0f, 1.0f);
  if (cosAngle >= cosHalf) return 1.0f;
  const float sinAngle = std::sqrt(std::max(0.0f, 1.0f - cosAngle * cosAngle));
  // cos(angle - half) for angle > half.
  return cosAngle * cosHalf + sinAngle * sinHalf;
}

inline float maxChannel(const glm::vec3& c) {
  return std::max({c.r, c.g, c.b});
}

}  // namespace lightcut_detail

/// B of the header comment for `node` at the receiver `sp`, clamp bound b = clampBound (inf = none). 0 when no VPL of
/// the node can light sp (behind it, or facing away); inf when sp lies in the box without a bound.
inline float lightcutBound(const ShadingPoint& sp, const LightTreeNode& node, float clampBound) {
  using namespace lightcut_detail;
  const glm::vec3& p = sp.hit.position;
  const glm::vec3& n = sp.hit.shadingNormal;
  const float cosO = glm::dot(n, sp.wo);
  if (!(cosO > 0.0f)) return 0.0f;  // f(x1) is 0 seen from below
  // Step 1: d_min, and the cone of directions from x1 holding the box's bounding sphere.
  const glm::vec3 closest = glm::clamp(p, node.boundsMin, node.boundsMax);
  const float dMin2 = glm::dot(closest - p, closest - p);
  const glm::vec3 toCentre = 0.5f * (node.boundsMin + node.boundsMax) - p;
  const float radius = 0.5f * glm::length(node.boundsMax - node.boundsMin);
  const float dist = glm::length(toCentre);
  const bool everywhere = !(dist > radius * 1.0001f) || !(dist > 0.0f);
  const glm::vec3 axis = everywhere ? n : toCentre / dist;
  const float sinB = everywhere ? 1.0f : radius / dist;
  const float cosB = everywhere ? -1.0f : std::sqrt(std::max(0.0f, 1.0f - sinB * sinB));
  // Step 2: the receiver's cosine.
  const float cos1 = everywhere ? 1.0f : cosMaxWithinCone(glm::dot(n, axis), cosB, sinB);
  if (!(cos1 > 0.0f)) return 0.0f;
  // Step 3: the VPLs' cosine: normals within the node's cone, directions toward x1 within the cone around -axis.
  float cos2 = 1.0f;
  if (!everywhere && node.coneCos > -1.0f) {
    const float cosN = node.coneCos, sinN = std::sqrt(std::max(0.0f, 1.0f - cosN * cosN));
    const float cosSum = cosN * cosB - sinN * sinB, sinSum = sinN * cosB + cosN * sinB;
    if (sinSum >= 0.0f) cos2 = cosMaxWithinCone(-glm::dot(node.coneAxis, axis), cosSum, sinSum);
  }
  if (!(cos2 > 0.0f)) return 0.0f;
  const float geometry = dMin2 > 0.0f ? cos1 * cos2 / dMin2 : kInfinity;
  // Step 4: the receiver's BRDF. Pure Lambert: f = baseColor / pi, constant.
  const BrdfParams& brdf = sp.brdf;
  if (brdf.metallic == 0.0f && brdf.specular == 0.0f) {
    const float f = maxChannel(brdf.baseColor) * kInvPi;
    return f > 0.0f ? f * std::min(geometry, clampBound) : 0.0f;  // no 0 * inf
  }
  // GGX: D at the smallest half-vector angle the directions toward the box allow.
  const float alpha = brdf.alpha();
  float cosH = 1.0f;
  if (!everywhere) {
    const glm::vec3 mirror = 2.0f * cosO * n - sp.wo;
    const float gamma = std::acos(std::clamp(glm::dot(mirror, axis), -1.0f, 1.0f));
    cosH = std::cos(0.5f * std::max(0.0f, gamma - std::acos(std::clamp(cosB, -1.0f, 1.0f))));
  }
  const float dMax = alpha < 1.0f ? brdf_detail::ggxD(cosH, alpha) : brdf_detail::ggxD(0.0f, alpha);
  const float fresnelMax = std::max(0.0f, (1.0f - brdf.metallic) * brdf.specular) + brdf.metallic;
  const float diffuse = (1.0f - brdf.metallic) * maxChannel(brdf.baseColor) * kInvPi;
  const float a2 = alpha * alpha;
  const float specularCos = dMax * fresnelMax * 0.5f * cos1 / (cosO * std::sqrt(cos1 * cos1 * (1.0f - a2) + a2));
  const float specular = dMax * fresnelMax * 0.5f / (cosO * alpha);
  // f cos1 bounds the unclamped side, f alone the clamped one (G_b <= b whatever the cosines).
  const float unclamped = dMin2 > 0.0f ? (diffuse * cos1 + specularCos) * cos2 / dMin2 : kInfinity;
  return std::min(unclamped, (diffuse + specular) * clampBound);
}

}  // namespace vplab
