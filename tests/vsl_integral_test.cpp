// The VSL transfer pieces (renderer/vpl/vsl_integral.h) against brute-force integration: the closed forms where they
// are exact, the approximation's limits (r -> 0 is the point VPL), and the approximation's error on glossy pairs.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "renderer/core/sampling.h"
#include "renderer/settings.h"
#include "renderer/vpl/vpl_contribution.h"
#include "renderer/vpl/vsl_integral.h"

namespace vplab {
namespace {

BrdfParams lambert(float albedo) {
  BrdfParams p;
  p.baseColor = glm::vec3(albedo);
  p.metallic = 0.0f;
  p.specular = 0.0f;
  return p;
}

BrdfParams metal(float roughness) {
  BrdfParams p;
  p.baseColor = glm::vec3(0.74f);
  p.metallic = 1.0f;
  p.roughness = roughness;
  return p;
}

BrdfParams plastic(float roughness) {
  BrdfParams p;
  p.baseColor = glm::vec3(0.74f);
  p.metallic = 0.0f;
  p.specular = 1.0f;
  p.roughness = roughness;
  return p;
}

glm::vec3 randomDirection(Rng& rng) {
  glm::vec2 u = rng.next2D();
  float z = 1.0f - 2.0f * u.x, s = std::sqrt(std::max(0.0f, 1.0f - z * z)), phi = 2.0f * kPi * u.y;
  return {s * std::cos(phi), s * std::sin(phi), z};
}

/// A random flat pair that faces each other: x1 at the origin with normal n1, x2 at distance `dist` in a direction of
/// x1's upper hemisphere, its normal facing back toward x1's side; viewer and incoming directions on the front sides.
struct Pair {
  VslEnd x1, x2;
};

Pair randomPair(Rng& rng, float dist, const BrdfParams& b1, const BrdfParams& b2) {
  Pair p;
  p.x1.normal = p.x1.geometricNormal = glm::vec3(0.0f, 0.0f, 1.0f);
  glm::vec3 dir = sampleCosineHemisphere(rng.next2D());
  p.x2.position = dir * dist;
  glm::vec3 n2 = randomDirection(rng);
  if (glm::dot(n2, dir) > 0.0f) n2 = -n2;
  p.x2.normal = p.x2.geometricNormal = n2;
  p.x1.wo = sampleCosineHemisphere(rng.next2D());
  Frame f2(n2);
  p.x2.wo = f2.toWorld(sampleCosineHemisphere(rng.next2D()));
  p.x1.brdf = b1;
  p.x2.brdf = b2;
  return p;
}

float relDiff(const glm::vec3& a, const glm::vec3& b) {
  float la = luminance(a), lb = luminance(b);
  return std::abs(la - lb) / std::max(lb, 1e-20f);
}

TEST(VslIntegral, UnclippedLambertClosedFormIsExact) {
  Rng rng(7);
  int checked = 0;
  for (int i = 0; i < 400 && checked < 40; ++i) {
    Pair p = randomPair(rng, 0.3f, lambert(0.7f), lambert(0.5f));
    float r = 0.02f + 0.2f * rng.next1D();
    if (!vslConeUnclipped(p.x1, p.x2, r)) continue;
    ++checked;
    glm::vec3 exact = vslTransferNumerical(p.x1, p.x2, r, 256);
    EXPECT_LT(relDiff(vslLambertTransfer(p.x1, p.x2, r), exact), 1e-3f) << "pair " << i << " r " << r;
    // The centre + ring rule of the approximation integrates the same quadratic exactly.
    EXPECT_LT(relDiff(vslApproxTransfer(p.x1, p.x2, r), exact), 1e-3f) << "pair " << i << " r " << r;
  }
  EXPECT_GE(checked, 20);
}

TEST(VslIntegral, InsideTheSphereLambertClosedFormIsExact) {
  Rng rng(11);
  for (int i = 0; i < 10; ++i) {
    Pair p = randomPair(rng, 0.05f, lambert(0.7f), lambert(0.5f));
    float r = 0.1f;  // x1 inside the sphere: Omega is every direction
    glm::vec3 exact = vslTransferNumerical(p.x1, p.x2, r, 512);
    EXPECT_LT(relDiff(vslApproxTransfer(p.x1, p.x2, r), exact), 2e-3f) << "pair " << i;
  }
}

TEST(VslIntegral, GgxDiskMassMatchesNumericalIntegral) {
  // Mass of P22 (alpha^2 = a2) over a disk of radius rho centred at distance s, by a polar grid over the disk that
  // is dense near its centre (t = rho q^2), where a narrow lobe may sit.
  for (float alpha : {0.04f, 0.2f, 0.7f})
    for (float s : {0.0f, 0.03f, 0.3f, 1.5f})
      for (float rho : {0.001f, 0.05f, 0.4f}) {
        double a2 = alpha * alpha, sum = 0.0;
        const int n = 400;
        for (int i = 0; i < n; ++i)
          for (int j = 0; j < n; ++j) {
            double q = (i + 0.5) / n, t = rho * q * q, phi = 2.0 * M_PI * (j + 0.5) / n;
            double x = s + t * std::cos(phi), y = t * std::sin(phi);
            double m2 = x * x + y * y;
            // dA = t dt dphi, dt = 2 rho q dq
            sum += a2 / (M_PI * (a2 + m2) * (a2 + m2)) * t * 2.0 * rho * q;
          }
        double mass = sum * 2.0 * M_PI / (static_cast<double>(n) * n);
        float omega = 0.37f;  // any positive value: the function returns mass / omega
        double got = ggxDiskMassPerSolidAngle(static_cast<float>(a2), s * s, rho * rho / omega, omega) * omega;
        EXPECT_NEAR(got / mass, 1.0, 2e-3) << "alpha " << alpha << " s " << s << " rho " << rho;
      }
}

TEST(VslIntegral, TinyRadiusIsThePointVpl) {
  Rng rng(3);
  const BrdfParams materials[] = {lambert(0.7f), metal(0.25f), plastic(0.2f)};
  for (int i = 0; i < 60; ++i) {
    Pair p = randomPair(rng, 0.4f, materials[i % 3], materials[(i / 3) % 3]);
    ShadingPoint sp;
    sp.hit.position = p.x1.position;
    sp.hit.shadingNormal = sp.hit.geometricNormal = p.x1.normal;
    sp.wo = p.x1.wo;
    sp.brdf = p.x1.brdf;
    Vpl vpl;
    vpl.position = p.x2.position;
    vpl.normal = vpl.geometricNormal = p.x2.normal;
    vpl.incoming = p.x2.wo;
    vpl.flux = glm::vec3(1.0f);
    glm::vec3 point = vplUnoccludedContribution(sp, vpl, p.x2.brdf, kInfinity);
    if (!(luminance(point) > 0.0f)) continue;
    EXPECT_LT(relDiff(vslApproxTransfer(p.x1, p.x2, 1e-5f), point), 1e-3f) << "pair " << i;
    EXPECT_LT(relDiff(vslApproxTransfer(p.x1, p.x2, 0.0f), point), 1e-4f) << "pair " << i;
  }
}

// The approximation against the brute-force integral on glossy pairs (a GGX end, lobes from alpha = 0.04 up, random
// orientations with r/d = 1/8): the error in total (sum of T over the pairs, what an image's mean sees) and per pair.
// The bounds are the measured errors (docs/methods.md) with a margin; two glossy ends are the least accurate case.
TEST(VslIntegral, GlossyApproximationErrorIsBounded) {
  Rng rng(5);
  struct Case {
    BrdfParams receiver, vpl;
    double maxBias, maxMeanAbs;
  };
  const Case cases[] = {{metal(0.25f), lambert(0.7f), 0.02, 0.05},  {lambert(0.7f), metal(0.25f), 0.05, 0.09},
                        {plastic(0.2f), lambert(0.7f), 0.02, 0.03}, {lambert(0.7f), plastic(0.2f), 0.02, 0.03},
                        {metal(0.5f), plastic(0.2f), 0.07, 0.1}};
  for (const Case& c : cases) {
    const BrdfParams e[2] = {c.receiver, c.vpl};
    double sumApprox = 0.0, sumExact = 0.0, sumAbsErr = 0.0;
    for (int i = 0; i < 200; ++i) {
      Pair p = randomPair(rng, 0.4f, e[0], e[1]);
      float r = 0.05f;
      float exact = luminance(vslTransferNumerical(p.x1, p.x2, r, 160));
      float approx = luminance(vslApproxTransfer(p.x1, p.x2, r));
      sumApprox += approx;
      sumExact += exact;
      sumAbsErr += std::abs(approx - exact);
    }
    std::printf("[ measured ] VSL approximation r/d = 0.125, %s x %s: total %+.2f %%, mean |error| %.2f %% of mean T\n",
                e[0].metallic > 0.0f ? "metal" : e[0].specular > 0.0f ? "plastic" : "lambert",
                e[1].metallic > 0.0f ? "metal" : e[1].specular > 0.0f ? "plastic" : "lambert",
                100.0 * (sumApprox / sumExact - 1.0), 100.0 * sumAbsErr / sumExact);
    EXPECT_NEAR(sumApprox / sumExact, 1.0, c.maxBias);
    EXPECT_LT(sumAbsErr / sumExact, c.maxMeanAbs);
  }
}

}  // namespace
}  // namespace vplab
