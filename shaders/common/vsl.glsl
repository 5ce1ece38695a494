// Virtual-spherical-light transfer T (Hasan et al. 2009): the deterministic approximation of
//   T = 1 / (pi r^2) * integral over the cone Omega of f(x1; wo, w) f(x2; w_in, -w) cos1+ cos2+ dw
// that renderer/vpl/vsl_integral.h derives and documents (docs/methods.md gives its measured error); every function
// here mirrors the C++ function of the same name line by line, with the same constants. A VPL's contribution is
// Phi T V. No random numbers: the same pixel gives the same value every frame.
#include "common/brdf.glsl"

const int kVslRingNodes = 6;

struct VslCone {
  vec3 axis;                 // unit direction x1 -> centre
  float cosThetaMax;         // -1 inside the sphere
  float sinThetaMax;         // r / d; 0 inside the sphere
  float oneMinusCos;         // 1 - cosThetaMax without cancellation (2 inside)
  float solidAngle;          // Omega
  float solidAngleOverArea;  // Omega / (pi r^2); 1 / d^2 as r -> 0
  bool inside;
};

VslCone vslCone(vec3 toCentre, float radius, vec3 fallbackAxis) {
  VslCone c;
  float dist2 = dot(toCentre, toCentre);
  float r2 = radius * radius;
  float invDist2 = 1.0 / max(dist2, 1e-30), invDist = sqrt(invDist2);
  c.axis = dist2 > 0.0 ? toCentre * invDist : fallbackAxis;
  // Written with selects: llvmpipe would run both branches anyway.
  c.inside = dist2 <= r2;
  float s2 = r2 * invDist2;  // sin^2 theta_max
  float root = sqrt(max(0.0, 1.0 - s2));
  float invOnePlusRoot = 1.0 / (1.0 + root);
  c.cosThetaMax = c.inside ? -1.0 : root;
  c.sinThetaMax = c.inside ? 0.0 : radius * invDist;
  c.oneMinusCos = c.inside ? 2.0 : s2 * invOnePlusRoot;
  c.solidAngle = 2.0 * kPi * c.oneMinusCos;
  c.solidAngleOverArea = c.inside ? 4.0 / r2 : 2.0 * invDist2 * invOnePlusRoot;
  return c;
}

mat3 vslFrameAround(vec3 n) {
  float s = n.z >= 0.0 ? 1.0 : -1.0;
  float a = -1.0 / (s + n.z);
  float b = n.x * n.y * a;
  return mat3(vec3(1.0 + s * n.x * n.x * a, s * b, -s * n.x), vec3(b, s + n.y * n.y * a, -n.y), n);
}

// One node of the rule: dots = (n1.w, g1.w, m2.w, g2.w); weight * (c1 c2, c1, c2) where both one-sided tests pass.
vec3 vslNode(float weight, vec4 dots) {
  vec2 c = max(dots.xz, 0.0);
  return dots.y > 0.0 && dots.w > 0.0 ? weight * vec3(c.x * c.y, c) : vec3(0.0);
}

// Means over the cone of cos1+ cos2+ (x), cos1+ (y) and cos2+ (z), with the one-sided tests g1.w > 0, g2.w > 0;
// m2 = -n2, g2 = -VPL geometric normal. Centre + ring rule; inside the sphere the closed forms over the sphere.
vec3 vslCosineMeans(VslCone cone, vec3 n1, vec3 g1, vec3 m2, vec3 g2) {
  if (cone.inside) {
    float cosG = clamp(dot(n1, m2), -1.0, 1.0);
    float g = acos(cosG);
    float product = (2.0 / 3.0) * ((kPi - g) * cosG + sqrt(max(0.0, 1.0 - cosG * cosG))) / cone.solidAngle;
    return vec3(product, vec2(0.125 * (1.0 + cosG)));
  }
  // The four normals' components in the cone's frame (transpose = inverse), one vector per axis (n1, g1, m2, g2):
  // a node's four dot products are z Z + x X + y Y, and opposite ring nodes share z Z.
  mat3 toLocal = transpose(vslFrameAround(cone.axis));
  vec3 l1 = toLocal * n1, lg1 = toLocal * g1, l2 = toLocal * m2, lg2 = toLocal * g2;
  vec4 X = vec4(l1.x, lg1.x, l2.x, lg2.x), Y = vec4(l1.y, lg1.y, l2.y, lg2.y), Z = vec4(l1.z, lg1.z, l2.z, lg2.z);
  float z = 1.0 - 2.0 * cone.oneMinusCos / 3.0;  // (1 + 2 cos theta_max) / 3
  float sinT = sqrt(max(0.0, (2.0 * cone.oneMinusCos / 3.0) * (1.0 + z)));
  // Nodes at 2 pi k / 6: (cos, sin) = (1, 0), (1/2, sqrt(3)/2), (-1/2, sqrt(3)/2) and their opposites.
  vec4 zc = z * Z, p0 = sinT * X, p1 = sinT * (0.5 * X + 0.8660254 * Y), p2 = sinT * (-0.5 * X + 0.8660254 * Y);
  const float w = 0.75 / float(kVslRingNodes);
  return vslNode(0.25, Z) + vslNode(w, zc + p0) + vslNode(w, zc - p0) + vslNode(w, zc + p1) + vslNode(w, zc - p1) +
         vslNode(w, zc + p2) + vslNode(w, zc - p2);
}

// Mass of the GGX slope distribution (alpha^2 = a2) over the disk of radius^2 rho2PerSolidAngle * solidAngle
// centred at slope length^2 s2, divided by solidAngle; the point-to-parallel-disk form factor without cancellation.
float ggxDiskMassPerSolidAngle(float a2, float s2, float rho2PerSolidAngle, float solidAngle) {
  float rho2 = rho2PerSolidAngle * solidAngle;
  float diff = s2 - rho2;
  float q = sqrt(diff * diff + a2 * (2.0 * (s2 + rho2) + a2));
  float a = a2 + s2;
  bool narrow = a > rho2;
  float num = narrow ? 2.0 * a2 * rho2PerSolidAngle : 0.5 * (q + rho2 - a);
  float den = narrow ? q * (q + a - rho2) : q * solidAngle;
  return num / max(den, num * solidAngle);
}

// A GGX lobe over the cone: mean <s cos_i>, coverage A B / (A B + alpha^2), the cone direction closest to the mirror
// direction of wo.
struct VslLobe {
  vec3 mean;
  float coverage;
  vec3 peak;
};

// The cone direction (around `axis`, the cone's own or its reverse) closest to the unit direction `dir`, given
// c = dir . axis and s = sqrt(1 - c^2).
vec3 vslClosestInCone(VslCone cone, vec3 axis, vec3 dir, float c, float s) {
  vec3 edge = s > 1e-6 ? axis * cone.cosThetaMax + (dir - c * axis) * (cone.sinThetaMax / max(s, 1e-6)) : axis;
  return cone.inside || c >= cone.cosThetaMax ? dir : edge;
}

// The GGX part of f(n; wo, w) times cos_i over the cone, w around `axis`.
// meanCos: the cone mean of this end's cos_i with the one-sided tests (vslCosineMeans), which carries the horizons.
VslLobe vslMeanSpecular(BrdfParams p, vec3 n, vec3 wo, vec3 axis, VslCone cone, float meanCos) {
  float cosO = dot(n, wo), cosI = dot(n, axis);
  vec3 h = wo + axis;
  float hl2 = dot(h, h);
  h *= inversesqrt(max(hl2, 1e-30));
  float cosH = dot(n, h);
  bool lobe = cosO > 0.0 && cosI > 0.0 && hl2 > 0.0 && cosH > 0.0 && (p.metallic > 0.0 || p.specular > 0.0);
  cosH = max(cosH, 1e-6);
  float vDotH = max(1e-6, dot(wo, h));
  float alpha = max(kMinGgxAlpha, p.roughness * p.roughness);
  float cosH2 = cosH * cosH;
  float invCosH = 1.0 / cosH, invVDotH = 1.0 / vDotH;
  float invCosH2 = invCosH * invCosH;
  float tan2 = max(0.0, 1.0 - cosH2) * invCosH2;
  // The cone's image in the slope plane: an ellipse of area det * Omega; the disk of its radial extent decides
  // whether it reaches the lobe, with the area factor of the small-cone limit (vsl_integral.h).
  float det = 0.25 * invVDotH * invCosH2 * invCosH;
  float a2 = alpha * alpha;
  float cosBetaNum = cosO - vDotH * cosH;
  float sin2Prod = max(0.0, 1.0 - vDotH * vDotH) * max(0.0, 1.0 - cosH2);
  float cb2 = sin2Prod > 1e-12 ? min(1.0, cosBetaNum * cosBetaNum / max(sin2Prod, 1e-12)) : 1.0;
  float radialDenom = 4.0 * kPi * cosH2 * cosH2 * (cb2 + vDotH * vDotH * (1.0 - cb2));
  float radialPerSolidAngle = 1.0 / radialDenom;
  float ab = det * cone.solidAngle / kPi, radial2 = radialPerSolidAngle * cone.solidAngle;
  // Centred-ellipse correction; its numerator cancels the area factor's denominator.
  float sr2 = invCosH2 * invCosH2, st2 = invCosH2;
  float ti2 = 0.25, tp2 = 0.25 * invVDotH * invVDotH;
  float frob2 = (sr2 * ti2 + st2 * tp2) * cb2 + (sr2 * tp2 + st2 * ti2) * (1.0 - cb2);
  float sumSq = frob2 * cone.solidAngle / kPi;
  float mass = ggxDiskMassPerSolidAngle(a2, tan2, radialPerSolidAngle, cone.solidAngle) *
               (det * radialDenom / kPi) * (radial2 + a2) * inversesqrt(ab * ab + a2 * sumSq + a2 * a2);
  // Bound for wide cones: P22's mass on the cone's side of the line touching the cone closest to the mirror
  // direction R, at the slope distance t (linear map 2 in the plane of n and wo, 2 cos_o across it).
  vec3 mirror = 2.0 * cosO * n - wo;
  float cosMirror = dot(mirror, axis);
  float sin2Mirror = max(0.0, 1.0 - cosMirror * cosMirror), sinMirror = sqrt(sin2Mirror);
  float sinDelta = sinMirror * cone.cosThetaMax - cosMirror * cone.sinThetaMax;
  float onePlusCosDelta = 1.0 + cosMirror * cone.cosThetaMax + sinMirror * cone.sinThetaMax;
  float across = dot(axis, cross(n, wo));
  float q = 1.0 - min(1.0 - cosO * cosO, across * across / max(sin2Mirror, 1e-12));
  float t2 = sinDelta * sinDelta / max(onePlusCosDelta * onePlusCosDelta * q, 1e-30);
  float root = sqrt(t2 + a2);
  float beyond = 0.5 * a2 / (root * (root + sqrt(t2)));
  float bound = sinDelta > 0.0 ? beyond : 1.0 - beyond;
  mass = cone.inside ? mass : min(mass, bound / max(cone.solidAngle, 1e-30));
  VslLobe result;
  result.coverage = lobe ? ab / (ab + a2) : 0.0;
  result.peak = vslClosestInCone(cone, axis, mirror, cosMirror, sinMirror);
  // The smooth factors where the lobe's mass is: between the axis and the peak, by coverage.
  vec3 we = normalize(axis + result.coverage * (result.peak - axis));
  vec3 he = normalize(wo + we);
  float cosIe = max(0.0, dot(n, we)), cosHe = max(1e-6, dot(n, he));
  float vDotHe = max(1e-6, dot(wo, he));
  float fw = brdfSchlickWeight(vDotHe);
  vec3 weight = (1.0 - p.metallic) * p.specular * (0.04 + 0.96 * fw) +
                p.metallic * (p.baseColor + (1.0 - p.baseColor) * fw);
  // For a cone small against the lobe, f is smooth over it: cos_i is its clipped mean there.
  float cosMean = meanCos + result.coverage * (cosIe - meanCos);
  vec3 s = weight * (brdfSmithVisibility(cosO, cosIe, alpha) * cosMean * 4.0 * vDotHe / cosHe * mass);
  result.mean = lobe ? s : vec3(0.0);
  return result;
}

// The diffuse part of f toward wi, with the Fresnel transmission at cos_i clamped to [0, 1].
vec3 vslDiffuseBrdf(BrdfParams p, vec3 n, vec3 wo, vec3 wi) {
  float cosO = dot(n, wo);
  float transmitO = 1.0 - p.specular * (0.04 + 0.96 * brdfSchlickWeight(cosO));
  float transmitI = 1.0 - p.specular * (0.04 + 0.96 * brdfSchlickWeight(max(0.0, dot(n, wi))));
  return cosO > 0.0 ? (1.0 - p.metallic) * transmitO * transmitI * p.baseColor * kInvPi : vec3(0.0);
}

// T for receiver (x1, n1, g1, wo, p1) and VPL (x2, n2, g2, wIn, p2) of radius r; r = 0 gives the unclamped point VPL.
vec3 vslApproxTransfer(vec3 x1, vec3 n1, vec3 g1, vec3 wo, BrdfParams p1, vec3 x2, vec3 n2, vec3 g2, vec3 wIn,
                       BrdfParams p2, float radius) {
  vec3 d = x2 - x1;
  VslCone cone = vslCone(d, radius, n1);
  vec3 a = cone.axis;
  vec3 c = vslCosineMeans(cone, n1, g1, -n2, -g2);
  vec3 d1 = vslDiffuseBrdf(p1, n1, wo, a), d2 = vslDiffuseBrdf(p2, n2, wIn, -a);
  vec3 mean = d1 * d2 * c.x;
#ifndef BRDF_LAMBERT_ONLY
  VslLobe s1 = vslMeanSpecular(p1, n1, wo, a, cone, c.y);
  VslLobe s2 = vslMeanSpecular(p2, n2, wIn, -a, cone, c.z);
  // A lobe's smooth partner: the other end's cosine, from <c1 c2> / <c1> for a cone small against the lobe to its
  // value where the lobe peaks for a cone that holds it.
  vec3 w1 = s1.peak, w2 = -s2.peak;
  float atPeak1 = dot(g1, w1) > 0.0 && dot(g2, w1) < 0.0 ? max(0.0, -dot(n2, w1)) : 0.0;
  float atPeak2 = dot(g1, w2) > 0.0 && dot(g2, w2) < 0.0 ? max(0.0, dot(n1, w2)) : 0.0;
  float productOverBoth = c.x / max(c.y * c.z, 1e-30);  // <c1 c2> / (<c1> <c2>)
  float mean1 = productOverBoth * c.z, mean2 = productOverBoth * c.y;  // <c1 c2> / <c1>, <c1 c2> / <c2>
  float partner1 = mean1 + s1.coverage * (atPeak1 - mean1), partner2 = mean2 + s2.coverage * (atPeak2 - mean2);
  vec3 lobes = d2 * s1.mean * partner1 + d1 * s2.mean * partner2 + s1.mean * s2.mean * productOverBoth;
  mean += c.x > 0.0 ? lobes : vec3(0.0);
#endif
  bool valid = dot(d, d) > 0.0 || radius > 0.0;
  return valid ? mean * cone.solidAngleOverArea : vec3(0.0);
}

// vslApproxTransfer for a VPL on a Lambert material (metallic = specular = 0): its lobe is zero, so T = f2 times what
// is left, and f2 Phi leaves the integral (the caller multiplies by it, GlVpl::lambertPower). Same terms as above with
// s2 = 0; the VPL-side lobe is the costlier half of the integral, and most VPLs of a scene lie on Lambert materials.
vec3 vslLambertVplTransfer(vec3 x1, vec3 n1, vec3 g1, vec3 wo, BrdfParams p1, vec3 x2, vec3 n2, vec3 g2, float radius) {
  vec3 d = x2 - x1;
  VslCone cone = vslCone(d, radius, n1);
  vec3 a = cone.axis;
  vec3 c = vslCosineMeans(cone, n1, g1, -n2, -g2);
  vec3 mean = vslDiffuseBrdf(p1, n1, wo, a) * c.x;
  VslLobe s1 = vslMeanSpecular(p1, n1, wo, a, cone, c.y);
  vec3 w1 = s1.peak;
  float atPeak1 = dot(g1, w1) > 0.0 && dot(g2, w1) < 0.0 ? max(0.0, -dot(n2, w1)) : 0.0;
  float mean1 = c.x / max(c.y, 1e-30);  // <c1 c2> / <c1>
  float partner1 = mean1 + s1.coverage * (atPeak1 - mean1);
  mean += c.x > 0.0 ? s1.mean * partner1 : vec3(0.0);
  bool valid = dot(d, d) > 0.0 || radius > 0.0;
  return valid ? mean * cone.solidAngleOverArea : vec3(0.0);
}

// The pure-Lambert case (BRDF_LAMBERT_ONLY): f(x1) and f(x2) Phi leave the integral, T = f1 f2 <c1 c2> Omega/(pi r^2);
// this returns <c1 c2> Omega / (pi r^2), the caller multiplies by f1 and f2 Phi.
float vslLambertCosineTransfer(vec3 x1, vec3 n1, vec3 g1, vec3 x2, vec3 n2, vec3 g2, float radius) {
  vec3 d = x2 - x1;
  VslCone cone = vslCone(d, radius, n1);
  float product = vslCosineMeans(cone, n1, g1, -n2, -g2).x;
  bool valid = dot(d, d) > 0.0 || radius > 0.0;
  return valid ? product * cone.solidAngleOverArea : 0.0;
}
