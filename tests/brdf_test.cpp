// The one BRDF (renderer/core/brdf.h): energy conservation (white furnace), reciprocity, and that sampleBrdf()
// really draws directions with the density brdfPdf() reports (numerical integration and a chi-square test).

#include "renderer/core/brdf.h"
#include "renderer/core/sampling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace vplab {
namespace {

const glm::vec3 kN(0.0f, 0.0f, 1.0f);

glm::vec3 dirFromCos(float cosTheta, float phi) {
  float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
  return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
}

BrdfParams params(float roughness, float metallic, float specular, glm::vec3 base = glm::vec3(1.0f)) {
  BrdfParams p;
  p.baseColor = base;
  p.roughness = roughness;
  p.metallic = metallic;
  p.specular = specular;
  return p;
}

/// Directional albedo int f cos dwi by stratified uniform sampling of (cos theta, phi): independent of the sampler.
glm::dvec3 albedoByQuadrature(const BrdfParams& p, const glm::vec3& wo, int n) {
  glm::dvec3 sum(0.0);
  Rng rng(11);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      float cosTheta = (static_cast<float>(i) + rng.next1D()) / static_cast<float>(n);
      float phi = 2.0f * kPi * (static_cast<float>(j) + rng.next1D()) / static_cast<float>(2 * n);
      glm::vec3 wi = dirFromCos(cosTheta, phi);
      sum += glm::dvec3(evaluateBrdf(p, kN, wo, wi)) * static_cast<double>(cosTheta);
    }
  // Each cell has solid angle (1/n) (2 pi / 2n).
  return sum * (2.0 * kPi / (2.0 * n * n));
}

/// The same integral estimated with sampleBrdf(): mean of f cos / pdf (invalid samples count as zero).
glm::dvec3 albedoBySampling(const BrdfParams& p, const glm::vec3& wo, int n) {
  glm::dvec3 sum(0.0);
  Rng rng(12);
  for (int i = 0; i < n; ++i) {
    BrdfSample s = sampleBrdf(p, kN, wo, {rng.next1D(), rng.next1D(), rng.next1D()});
    if (s.valid()) sum += glm::dvec3(s.f) * static_cast<double>(glm::dot(kN, s.wi) / s.pdf);
  }
  return sum / static_cast<double>(n);
}

struct Case {
  float roughness, metallic, specular;
};
const Case kCases[] = {{0.3f, 0.0f, 1.0f}, {0.6f, 0.0f, 1.0f}, {1.0f, 0.0f, 1.0f}, {0.3f, 1.0f, 1.0f},
                       {0.6f, 1.0f, 1.0f}, {1.0f, 1.0f, 1.0f}, {0.5f, 0.5f, 1.0f}, {0.5f, 0.0f, 0.5f}};
const float kCosO[] = {0.15f, 0.5f, 0.95f};

TEST(BrdfFurnace, LambertDielectricWithoutSpecularReflectsEverything) {
  // specular 0 makes the dielectric exactly Lambertian: albedo 1 for a white base colour at every angle and
  // roughness.
  for (float roughness : {0.2f, 1.0f})
    for (float cosO : kCosO) {
      glm::dvec3 a = albedoByQuadrature(params(roughness, 0.0f, 0.0f), dirFromCos(cosO, 0.3f), 64);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], 1.0, 2e-3) << "roughness " << roughness << " cos " << cosO;
    }
}

TEST(BrdfFurnace, WhiteAlbedoNeverExceedsOneForConductorsAndPureLambert) {
  // Roughness >= 0.3: sharper lobes need a finer quadrature grid than a fast test can afford.
  for (float roughness : {0.3f, 0.45f, 0.6f, 1.0f})
    for (float metallic : {0.0f, 1.0f})
      for (float cosO : kCosO) {
        // specular 0 for the dielectric: WhiteDielectricWithSpecularNeverGainsEnergy covers specular > 0.
        BrdfParams p = params(roughness, metallic, 0.0f);
        glm::dvec3 q = albedoByQuadrature(p, dirFromCos(cosO, 1.1f), 128);
        // Single-scattering GGX loses energy (most at high roughness) but never gains it.
        for (int c = 0; c < 3; ++c) {
          EXPECT_LE(q[c], 1.0 + 5e-3) << "roughness " << roughness << " metallic " << metallic << " cos " << cosO;
          EXPECT_GT(q[c], 0.25) << "roughness " << roughness << " metallic " << metallic << " cos " << cosO;
        }
      }
}

TEST(BrdfFurnace, RoughWhiteMetalMatchesClosedForm) {
  // alpha = 1: D = 1/pi and the height-correlated V = 1 / (2 (cos_o + cos_i)), F = 1 for a white conductor, so the
  // albedo is int_0^1 mu / (mu + cos_o) dmu = 1 - cos_o ln(1 + 1/cos_o).
  for (float cosO : kCosO) {
    double expected = 1.0 - cosO * std::log(1.0 + 1.0 / cosO);
    glm::dvec3 q = albedoByQuadrature(params(1.0f, 1.0f, 1.0f), dirFromCos(cosO, 0.0f), 128);
    EXPECT_NEAR(q.g, expected, 2e-3) << "cos " << cosO;
  }
}

TEST(BrdfFurnace, WhiteDielectricWithSpecularNeverGainsEnergy) {
  // glTF's fresnel_mix (diffuse weighted by 1 - F(v.h)) reflects up to 1.8x the incident energy at grazing angles for
  // a white dielectric; brdf.h weights the diffuse lobe by the Fresnel transmission at both ends instead. Smooth to
  // rough, normal to grazing incidence: the albedo stays <= 1. It may not collapse either: at cos_o = 0.15 the
  // Fresnel transmission 1 - F = 0.53 bounds the diffuse part from below.
  for (float roughness : {0.05f, 0.1f, 0.3f, 0.5f, 1.0f})
    for (float cosO : kCosO) {
      double albedo = albedoByQuadrature(params(roughness, 0.0f, 1.0f), dirFromCos(cosO, 0.5f), 128).g;
      EXPECT_LE(albedo, 1.0 + 5e-3) << "roughness " << roughness << " cos " << cosO;
      EXPECT_GT(albedo, 0.45) << "roughness " << roughness << " cos " << cosO;
    }
}

TEST(BrdfFurnace, SampledEstimateMatchesQuadrature) {
  // E[f cos / pdf] under sampleBrdf() equals the albedo integral only if the reported pdf is the sampling density.
  for (const Case& k : kCases)
    for (float cosO : kCosO) {
      BrdfParams p = params(k.roughness, k.metallic, k.specular, glm::vec3(0.9f, 0.6f, 0.3f));
      glm::vec3 wo = dirFromCos(cosO, 2.0f);
      glm::dvec3 q = albedoByQuadrature(p, wo, 128);
      glm::dvec3 s = albedoBySampling(p, wo, 100000);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(s[c], q[c], 0.01 * q[c] + 1e-3)
            << "roughness " << k.roughness << " metallic " << k.metallic << " cos " << cosO << " channel " << c;
    }
}

TEST(BrdfReciprocity, SwappingDirectionsGivesTheSameValue) {
  Rng rng(5);
  for (const Case& k : kCases) {
    BrdfParams p = params(k.roughness, k.metallic, k.specular, glm::vec3(0.8f, 0.4f, 0.2f));
    for (int i = 0; i < 200; ++i) {
      glm::vec3 a = dirFromCos(std::max(0.02f, rng.next1D()), 2.0f * kPi * rng.next1D());
      glm::vec3 b = dirFromCos(std::max(0.02f, rng.next1D()), 2.0f * kPi * rng.next1D());
      glm::vec3 fab = evaluateBrdf(p, kN, a, b), fba = evaluateBrdf(p, kN, b, a);
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(fab[c], fba[c], 1e-5f * (1.0f + fab[c]));
    }
  }
}

TEST(BrdfReciprocity, BelowTheSurfaceIsBlack) {
  BrdfParams p = params(0.5f, 0.0f, 1.0f);
  glm::vec3 up = dirFromCos(0.7f, 0.0f), down = -dirFromCos(0.6f, 1.0f);
  EXPECT_EQ(evaluateBrdf(p, kN, up, down), glm::vec3(0.0f));
  EXPECT_EQ(evaluateBrdf(p, kN, down, up), glm::vec3(0.0f));
  EXPECT_EQ(brdfPdf(p, kN, up, down), 0.0f);
}

TEST(BrdfSampling, PdfIntegratesToTheValidSampleFraction) {
  // int pdf dwi over the upper hemisphere is 1 minus the share of specular samples reflected below the horizon
  // (sampleBrdf() rejects those), and exactly 1 for a purely diffuse lobe.
  for (const Case& k : kCases)
    for (float cosO : kCosO) {
      BrdfParams p = params(k.roughness, k.metallic, k.specular, glm::vec3(0.7f));
      glm::vec3 wo = dirFromCos(cosO, 0.4f);
      const int n = 256;
      double integral = 0.0;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < 2 * n; ++j) {
          float cosTheta = (i + 0.5f) / n, phi = 2.0f * kPi * (j + 0.5f) / (2 * n);
          integral += brdfPdf(p, kN, wo, dirFromCos(cosTheta, phi));
        }
      integral *= 2.0 * kPi / (2.0 * n * n);
      Rng rng(21);
      int valid = 0;
      const int samples = 50000;
      for (int i = 0; i < samples; ++i)
        valid += sampleBrdf(p, kN, wo, {rng.next1D(), rng.next1D(), rng.next1D()}).valid();
      double fraction = static_cast<double>(valid) / samples;
      EXPECT_LE(integral, 1.0 + 5e-3);
      EXPECT_NEAR(integral, fraction, 0.01) << "roughness " << k.roughness << " metallic " << k.metallic;
    }
  BrdfParams lambert = params(1.0f, 0.0f, 0.0f);
  double integral = 0.0;
  for (int i = 0; i < 128; ++i) integral += brdfPdf(lambert, kN, kN, dirFromCos((i + 0.5f) / 128, 0.0f));
  EXPECT_NEAR(integral * 2.0 * kPi / 128.0, 1.0, 1e-4);
}

TEST(BrdfSampling, ChiSquareHistogramMatchesPdf) {
  // Pearson chi-square of sample counts in (cos theta, phi) cells against n * integral of brdfPdf over each cell
  // (pbrt's chi2 test): cells expecting fewer than 5 samples are pooled, and the statistic must stay within
  // 5 standard deviations of its mean (dof) for a correct sampler.
  const int thetaBins = 16, phiBins = 32, samples = 200000, sub = 4;
  for (const Case& k : {Case{0.3f, 0.0f, 1.0f}, Case{0.6f, 1.0f, 1.0f}, Case{1.0f, 0.0f, 1.0f}})
    for (float cosO : {0.3f, 0.8f}) {
      BrdfParams p = params(k.roughness, k.metallic, k.specular, glm::vec3(0.5f));
      glm::vec3 wo = dirFromCos(cosO, 0.0f);
      std::vector<double> observed(thetaBins * phiBins, 0.0), expected(thetaBins * phiBins, 0.0);
      Rng rng(31);
      for (int i = 0; i < samples; ++i) {
        BrdfSample s = sampleBrdf(p, kN, wo, {rng.next1D(), rng.next1D(), rng.next1D()});
        if (!s.valid()) continue;
        float phi = std::atan2(s.wi.y, s.wi.x);
        if (phi < 0.0f) phi += 2.0f * kPi;
        int ti = std::min(thetaBins - 1, static_cast<int>(s.wi.z * thetaBins));
        int pi = std::min(phiBins - 1, static_cast<int>(phi / (2.0f * kPi) * phiBins));
        observed[ti * phiBins + pi] += 1.0;
      }
      const double cellArea = (1.0 / thetaBins) * (2.0 * kPi / phiBins) / (sub * sub);
      for (int ti = 0; ti < thetaBins; ++ti)
        for (int pi = 0; pi < phiBins; ++pi)
          for (int a = 0; a < sub; ++a)
            for (int b = 0; b < sub; ++b) {
              float cosTheta = (ti + (a + 0.5f) / sub) / thetaBins;
              float phi = 2.0f * kPi * (pi + (b + 0.5f) / sub) / phiBins;
              expected[ti * phiBins + pi] += samples * cellArea * brdfPdf(p, kN, wo, dirFromCos(cosTheta, phi));
            }
      double chi2 = 0.0, pooledObs = 0.0, pooledExp = 0.0;
      int dof = -1;
      for (std::size_t c = 0; c < observed.size(); ++c) {
        if (expected[c] < 5.0) {
          pooledObs += observed[c];
          pooledExp += expected[c];
          continue;
        }
        chi2 += (observed[c] - expected[c]) * (observed[c] - expected[c]) / expected[c];
        ++dof;
      }
      if (pooledExp >= 5.0) {
        chi2 += (pooledObs - pooledExp) * (pooledObs - pooledExp) / pooledExp;
        ++dof;
      }
      ASSERT_GT(dof, 20);
      EXPECT_LT(chi2, dof + 5.0 * std::sqrt(2.0 * dof))
          << "roughness " << k.roughness << " metallic " << k.metallic << " cos " << cosO << " dof " << dof;
    }
}

}  // namespace
}  // namespace vplab
