// The reference path tracer through homogeneous media (docs/theory.md §16) against answers it cannot influence: the
// furnace filled with a non-absorbing medium stays at L = 2, single scattering of a point light equals a 1-D integral
// evaluated by adaptive quadrature, a purely absorbing box attenuates an emitter by exp(-sigma_a length), vacuum
// media leave images bit-identical, and extreme media (optically huge, one channel without interaction, a
// directional light in a medium filling all space) render finite images.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <glm/gtc/matrix_transform.hpp>
#include <string>

#include "renderer/image/metrics.h"
#include "renderer/offline/camera_sample.h"
#include "renderer/offline/emitter_mask.h"
#include "renderer/offline/light_sampler.h"
#include "renderer/offline/medium_direct.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/offline/path_tracer.h"
#include "renderer/offline/progressive.h"
#include "renderer/scene/medium.h"
#include "tests/media_test_util.h"
#include "tests/test_scenes.h"

namespace vplab {
namespace {

using test::boxMedium;
using test::spaceMedium;

Settings smallSettings(int size, int spp) {
  return test::smallReferenceSettings(size, spp);
}

glm::dvec3 imageMean(const Image& image) {
  glm::dvec3 sum(0.0);
  for (const glm::vec3& p : image.pixels) sum += glm::dvec3(p);
  return sum / static_cast<double>(image.size());
}

bool allFinite(const Image& image) {
  for (const glm::vec3& p : image.pixels)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return false;
  return true;
}

/// Mean and standard error per channel of n referenceRadiance() samples along one ray.
struct RayEstimate {
  glm::dvec3 mean{0.0};
  glm::dvec3 stderr_{0.0};
  int nonFinite = 0;
};
RayEstimate estimateRay(const OfflineScene& offline, const glm::vec3& origin, const glm::vec3& dir, int n,
                        Components components, int maxDepth, uint64_t seed,
                        DistanceSampling distanceSampling = DistanceSampling::Mis) {
  glm::dvec3 sum(0.0), sum2(0.0);
  RayEstimate e;
  for (int i = 0; i < n; ++i) {
    Rng rng(hashKey(seed, static_cast<uint64_t>(i)));
    glm::vec3 l = referenceRadiance(offline.embree(), offline.lights(), origin, dir, maxDepth, components, rng, nullptr,
                                    distanceSampling);
    if (!std::isfinite(l.x) || !std::isfinite(l.y) || !std::isfinite(l.z)) {
      ++e.nonFinite;
      continue;
    }
    sum += glm::dvec3(l);
    sum2 += glm::dvec3(l) * glm::dvec3(l);
  }
  const double m = n - e.nonFinite;
  e.mean = sum / m;
  glm::dvec3 var = glm::max(sum2 / m - e.mean * e.mean, glm::dvec3(0.0));
  e.stderr_ = glm::sqrt(var / m);
  return e;
}

// --- the furnace: a non-absorbing medium keeps L = 1 / (1 - albedo) = 2 everywhere (docs/theory.md §16) ----------

// The walls hold L = 2 (emission 1, reflected 1), seen through the medium: a pixel gets 2 T from the walls and
// 2 (1 - T) from the medium's in-scattering (T its camera ray's transmittance to the wall). The image mean minus the
// walls' exact part, 2 mean(T), is the medium's part, checked per channel against its exact value 2 (1 - mean(T))
// (test::furnaceMediumPart), so that a medium thinner than these (whose part of the image is small, and the
// image mean's bound of 0.02 large beside it) stays pinned: the smallest part here is the box's red, 0.70 of the 2.
// Measured: the medium's part within -0.15 % and +0.22 % of exact in every furnace and channel (the image mean's
// standard error of 0.005 is 0.7 % of 0.70). Bound 2 % of the part (3 standard errors of the smallest), below the 5 %
// of an error in the in-scattering, which fails it (checked: the camera paths that scatter first in the medium times
// 1.05 or 0.95).
void expectMediumFurnace(const Medium& medium, const char* what) {
  Scene scene = test::makeFurnaceBox(0.5f);
  scene.media.push_back(medium);
  OfflineScene offline(scene);
  // 524k paths: the image mean's standard error is about 0.005 (per-sample spread below 3.5), so 1 % is 4 of them.
  Settings s = smallSettings(32, 512);
  // Every medium event is a vertex: between two walls (mean chord 4V/S = 4/3) a path scatters up to ~5 times at
  // sigma_s = 4, so it needs far more vertices than the empty furnace. Russian roulette ends it long before 512.
  s.maxDepth = 512;
  ProgressiveResult r = renderReference(offline, s);
  EXPECT_EQ(r.nonFiniteSamples, 0u) << what;
  const glm::dvec3 mean = imageMean(r.image);
  // The per-sample spread, measured along the camera's axis, bounds every pixel's mean of 32 samples.
  RayEstimate axis =
      estimateRay(offline, scene.camera.position, scene.camera.forward, 4096, Components::All, s.maxDepth, 99);
  EXPECT_EQ(axis.nonFinite, 0) << what;
  const glm::dvec3 exactMedium = test::furnaceMediumPart(offline, s.width, s.height);
  const glm::dvec3 mediumError = (mean - 2.0) / exactMedium;
  int outliers = 0;
  double worst = 0.0;
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(mean[c], 2.0, 0.02) << what << " channel " << c;
    EXPECT_NEAR(mediumError[c], 0.0, 0.02)
        << what << " channel " << c << ": the medium's part " << mean[c] - 2.0 + exactMedium[c] << ", exact "
        << exactMedium[c];
    const double sigmaSample = axis.stderr_[c] * std::sqrt(4096.0);
    EXPECT_NEAR(axis.mean[c], 2.0, std::max(5.0 * axis.stderr_[c], 0.01)) << what << " axis channel " << c;
    // 6 standard deviations of a pixel's mean: about 1e-9 per pixel for a normal distribution.
    const double bound = 6.0 * sigmaSample / std::sqrt(static_cast<double>(s.samplesPerPixel));
    for (const glm::vec3& p : r.image.pixels) {
      worst = std::max(worst, std::abs(p[c] - 2.0) / bound);
      outliers += std::abs(p[c] - 2.0) > bound;
    }
  }
  EXPECT_EQ(outliers, 0) << what;
  std::printf(
      "%s: image mean (%.4f %.4f %.4f), axis (%.4f %.4f %.4f) +- (%.4f %.4f %.4f), worst pixel %.2f of its "
      "6-sigma bound, %.2f s\n",
      what, mean.x, mean.y, mean.z, axis.mean.x, axis.mean.y, axis.mean.z, axis.stderr_.x, axis.stderr_.y,
      axis.stderr_.z, worst, r.seconds);
  std::printf("[ measured ] %s: the medium's part (%.4f %.4f %.4f), exact (%.4f %.4f %.4f): %+.2f %+.2f %+.2f %%\n",
              what, mean.x - 2.0 + exactMedium.x, mean.y - 2.0 + exactMedium.y, mean.z - 2.0 + exactMedium.z,
              exactMedium.x, exactMedium.y, exactMedium.z, 100.0 * mediumError.x, 100.0 * mediumError.y,
              100.0 * mediumError.z);
}

TEST(MediaReferenceFurnace, IsotropicMediumFillingSpaceKeepsTwo) {
  expectMediumFurnace(spaceMedium(glm::vec3(0.0f), glm::vec3(2.0f), 0.0f), "space, sigma_s 2, g 0");
}

TEST(MediaReferenceFurnace, ForwardChromaticMediumFillingSpaceKeepsTwo) {
  expectMediumFurnace(spaceMedium(glm::vec3(0.0f), glm::vec3(0.5f, 2.0f, 4.0f), 0.7f),
                      "space, sigma_s (0.5 2 4), g 0.7");
}

TEST(MediaReferenceFurnace, ChromaticBoxInsideKeepsTwo) {
  const glm::vec3 centre(0.1f, -0.2f, 0.3f), half(0.5f, 0.4f, 0.6f);
  expectMediumFurnace(boxMedium(centre, half, glm::vec3(0.0f), glm::vec3(0.5f, 2.0f, 4.0f), 0.0f),
                      "box, sigma_s (0.5 2 4), g 0");
  expectMediumFurnace(boxMedium(centre, half, glm::vec3(0.0f), glm::vec3(0.5f, 2.0f, 4.0f), 0.7f),
                      "box, sigma_s (0.5 2 4), g 0.7");
}

TEST(MediaReferenceFurnace, BackwardBoxAroundTheCameraKeepsTwo) {
  // The camera (at the origin) inside a rotated box.
  Medium m =
      boxMedium(glm::vec3(0.0f), glm::vec3(0.7f, 0.5f, 0.6f), glm::vec3(0.0f), glm::vec3(3.0f, 1.0f, 2.0f), -0.5f);
  const glm::mat4 rot = glm::rotate(glm::mat4(1.0f), 0.6f, glm::normalize(glm::vec3(1.0f, 2.0f, 0.5f)));
  m.worldFromBox = rot * m.worldFromBox;
  m.boxFromWorld = glm::inverse(m.worldFromBox);
  expectMediumFurnace(m, "rotated box around the camera, sigma_s (3 1 2), g -0.5");
}

// --- single scattering of a point light (docs/theory.md §16) ------------------------------------------------------

/// Adaptive Simpson in double (Lyness 1969), to a relative tolerance of the whole integral.
double adaptiveSimpson(const std::function<double(double)>& f, double a, double b, double fa, double fm, double fb,
                       double whole, double eps, int depth) {
  const double m = 0.5 * (a + b), lm = 0.5 * (a + m), rm = 0.5 * (m + b);
  const double flm = f(lm), frm = f(rm);
  const double left = (m - a) / 6.0 * (fa + 4.0 * flm + fm), right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
  const double delta = left + right - whole;
  if (depth <= 0 || std::abs(delta) <= 15.0 * eps) return left + right + delta / 15.0;
  return adaptiveSimpson(f, a, m, fa, flm, fm, left, 0.5 * eps, depth - 1) +
         adaptiveSimpson(f, m, b, fm, frm, fb, right, 0.5 * eps, depth - 1);
}
double integrate(const std::function<double(double)>& f, double a, double b, double eps) {
  const double fa = f(a), fb = f(b), fm = f(0.5 * (a + b));
  return adaptiveSimpson(f, a, b, fa, fm, fb, (b - a) / 6.0 * (fa + 4.0 * fm + fb), eps, 50);
}

/// integral_0^inf exp(-sigma_t t) sigma_s f_p(cos) I exp(-sigma_t d(t)) / d(t)^2 dt for one channel, the camera ray
/// o + t w, the light at p. cos is the cosine between the light's direction of travel before scattering, x - p, and
/// after, -w: cos = dot(wi, w) with wi = (p - x) / d pointing toward the light.
/// With tIn, tOut: the medium only on [tIn, tOut) of the ray (a slab it crosses, the light inside it).
double singleScattering(const glm::dvec3& o, const glm::dvec3& w, const glm::dvec3& p, double intensity, double sigmaA,
                        double sigmaS, double g, double tIn = 0.0, double tOut = HUGE_VAL) {
  const double sigmaT = sigmaA + sigmaS;
  auto f = [&](double t) {
    const glm::dvec3 x = o + (t + tIn) * w;
    const glm::dvec3 toLight = p - x;
    const double d = glm::length(toLight);
    const double cosT = glm::dot(toLight / d, w);
    const double denom = 1.0 + g * g - 2.0 * g * cosT;
    const double phase = (1.0 - g * g) / (4.0 * M_PI * denom * std::sqrt(denom));
    return std::exp(-sigmaT * t) * sigmaS * phase * intensity * std::exp(-sigmaT * d) / (d * d);
  };
  // Split at the light's closest approach, where the 1/d^2 peak is; beyond 60 mean free paths nothing is left.
  const double tEnd = std::min(tOut - tIn, std::max(0.0, glm::dot(p - o, w) - tIn) + 60.0 / sigmaT);
  const double tClosest = std::clamp(glm::dot(p - o, w) - tIn, 0.0, tEnd);
  return integrate(f, 0.0, tClosest, 1e-12) + integrate(f, tClosest, tEnd, 1e-12);
}

/// A scene of a point light in a medium and one small black triangle out of every ray's way (the BVH and the scene
/// bounds want some geometry).
Scene pointLightInMedium(const glm::vec3& lightPos, float intensity, const Medium& medium) {
  Scene s;
  s.sourcePath = "point-light-in-medium";
  uint32_t black = test::addLambertMaterial(s, glm::vec3(0.0f));
  test::addQuad(s, {-0.01f, -30.0f, -0.01f}, {0.01f, -30.0f, -0.01f}, {0.01f, -30.0f, 0.01f}, {-0.01f, -30.0f, 0.01f},
                black, {0, 1, 0});
  PunctualLight l;
  l.name = "point";
  l.type = PunctualLight::Type::Point;
  l.position = lightPos;
  l.intensity = glm::vec3(intensity);
  s.punctualLights.push_back(l);
  s.camera.position = glm::vec3(0.0f);
  s.camera.forward = glm::vec3(0.0f, 0.0f, -1.0f);
  s.camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
  s.media.push_back(medium);
  s.finalize();
  return s;
}

void expectSingleScattering(const Medium& medium, const char* what) {
  const glm::vec3 light(0.0f, 1.0f, -2.0f);
  const float intensity = 10.0f;
  Scene scene = pointLightInMedium(light, intensity, medium);
  OfflineScene offline(scene);
  const glm::vec3 o(0.0f), w(0.0f, 0.0f, -1.0f);
  const int n = 200000;
  RayEstimate e = estimateRay(offline, o, w, n, Components::Direct, 8, 1234);
  EXPECT_EQ(e.nonFinite, 0) << what;
  for (int c = 0; c < 3; ++c) {
    const double exact = singleScattering(glm::dvec3(o), glm::dvec3(w), glm::dvec3(light), intensity, medium.sigmaA[c],
                                          medium.sigmaS[c], medium.g);
    EXPECT_NEAR(e.mean[c], exact, std::min(0.01 * exact, 4.0 * e.stderr_[c] + 1e-4 * exact))
        << what << " channel " << c << " stderr " << e.stderr_[c];
    // The estimate's own noise must be small enough for the 1 % test to mean something.
    EXPECT_LT(e.stderr_[c], 0.004 * exact) << what << " channel " << c;
    std::printf("%s channel %d: quadrature %.6f, reference %.6f +- %.6f (%+.3f %%)\n", what, c, exact, e.mean[c],
                e.stderr_[c], 100.0 * (e.mean[c] / exact - 1.0));
  }
}

TEST(MediaReferenceSingleScattering, PointLightInMediumFillingSpace) {
  expectSingleScattering(spaceMedium(glm::vec3(0.2f), glm::vec3(0.3f), 0.0f), "space, g 0");
  expectSingleScattering(spaceMedium(glm::vec3(0.2f), glm::vec3(0.3f), 0.6f), "space, g 0.6");
  expectSingleScattering(spaceMedium(glm::vec3(0.2f), glm::vec3(0.3f), -0.4f), "space, g -0.4");
}

TEST(MediaReferenceSingleScattering, ChromaticMediumInALargeBox) {
  // Half size 100: exp(-sigma_t 100) of the integral lies beyond the box, far below the tolerance.
  expectSingleScattering(boxMedium(glm::vec3(0.0f, 0.0f, -5.0f), glm::vec3(100.0f), glm::vec3(0.2f, 0.1f, 0.05f),
                                   glm::vec3(0.1f, 0.3f, 0.6f), 0.5f),
                         "box of half size 100, chromatic, g 0.5");
}

TEST(MediaReferenceSingleScattering, RenderedPixelsAreFinite) {
  Scene scene =
      pointLightInMedium(glm::vec3(0.0f, 1.0f, -2.0f), 10.0f, spaceMedium(glm::vec3(0.2f), glm::vec3(0.3f), 0.6f));
  OfflineScene offline(scene);
  Settings s = smallSettings(16, 16);
  ProgressiveResult direct = renderReference(offline, s);
  EXPECT_EQ(direct.nonFiniteSamples, 0u);
  EXPECT_TRUE(allFinite(direct.image));
  EXPECT_GT(imageMean(direct.image).g, 0.0);
}

// --- distance sampling toward the light: equiangular + free flight, MIS (docs/theory.md §24) ----------------------

// The equiangular density integrates to one over its span wherever the light lies (beside the span, beyond its ends,
// almost on the line), and sampleEquiangular() returns it for the t it draws, with the mass below the span's middle
// that the density says.
TEST(MediaDistanceMis, EquiangularPdfIntegratesToOneOverTheSegment) {
  const glm::vec3 o(0.2f, -0.1f, 0.3f), d = glm::normalize(glm::vec3(0.3f, 0.4f, -1.0f));
  const float a = 0.5f, b = 3.0f;
  const std::vector<MediumInterval> intervals{{a, b, 0}};
  for (const glm::vec3& p : {o + d * 1.2f + glm::vec3(0.3f, 0.0f, 0.1f), o + d * 1.7f + glm::vec3(0.0f, 0.002f, 0.0f),
                             o - d * 2.0f + glm::vec3(0.0f, 0.5f, 0.0f), o + d * 5.0f + glm::vec3(1.0f, 0.0f, 0.0f)}) {
    auto pdf = [&](double t) { return equiangularPdf(o, d, a, b, p, 1e-6f, static_cast<float>(t)); };
    // Split at the peak (the foot of the perpendicular, when it lies on the span).
    const double peak = std::clamp(static_cast<double>(glm::dot(p - o, d)), double(a), double(b));
    const double integral = integrate(pdf, a, peak, 1e-7) + integrate(pdf, peak, std::nextafter(b, 0.0f), 1e-7);
    EXPECT_NEAR(integral, 1.0, 2e-3) << p.x << " " << p.y << " " << p.z;
    EXPECT_EQ(equiangularPdf(o, d, a, b, p, 1e-6f, a - 0.01f), 0.0f);
    EXPECT_EQ(equiangularPdf(o, d, a, b, p, 1e-6f, b), 0.0f);
    const double mid = 0.5 * (a + b), split = std::min(peak, mid);
    const double middle = integrate(pdf, a, split, 1e-7) + integrate(pdf, split, mid, 1e-7);
    Rng rng(7);
    int below = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
      float t = 0.0f, pdf = 0.0f;
      ASSERT_NE(sampleEquiangular(intervals, o, d, a, b, p, rng.next1D(), 1e-6f, t, pdf), nullptr);
      EXPECT_NEAR(pdf, equiangularPdf(o, d, a, b, p, 1e-6f, t), 1e-5f * pdf);
      below += t < 0.5f * (a + b) ? 1 : 0;
    }
    // 5 binomial standard deviations.
    EXPECT_NEAR(below / double(n), middle, 5.0 * std::sqrt(middle * (1.0 - middle) / n));
  }
}

// On a homogeneous slab with a point light inside it, close to the camera ray, the lights' single scattering by free
// flights alone, by equiangular sampling alone and by both with MIS have one expectation: each equals the quadrature
// within 4 of its standard errors. Grey and chromatic (the free flight's density mixes the channels by spectral MIS),
// forward scattering (g = 0.7, where neither technique follows the phase function) and isotropic with the light 1 cm
// from the ray, where the free flights' 1/d^2 is at its worst.
TEST(MediaDistanceMis, FreeFlightEquiangularAndMisAgreeOnASlab) {
  struct Case {
    glm::vec3 sigmaS;
    float g, offset;
  };
  for (const Case& k : {Case{glm::vec3(0.8f), 0.7f, 0.08f}, Case{glm::vec3(0.3f, 0.8f, 2.0f), 0.7f, 0.08f},
                        Case{glm::vec3(0.8f), 0.0f, 0.01f}}) {
    const glm::vec3 light(0.0f, k.offset, -2.0f);
    // z in [-3, -1]: the ray along -z crosses 2 m of medium, the light sits beside it in the middle.
    const Medium slab =
        boxMedium(glm::vec3(0.0f, 0.0f, -2.0f), glm::vec3(50.0f, 50.0f, 1.0f), glm::vec3(0.05f), k.sigmaS, k.g);
    Scene scene = pointLightInMedium(light, 1.0f, slab);
    OfflineScene offline(scene);
    const glm::vec3 o(0.0f), w(0.0f, 0.0f, -1.0f);
    RayEstimate e[3];
    const DistanceSampling techniques[3] = {DistanceSampling::Mis, DistanceSampling::FreeFlight,
                                            DistanceSampling::Equiangular};
    const char* names[3] = {"mis", "free flight", "equiangular"};
    for (int i = 0; i < 3; ++i) e[i] = estimateRay(offline, o, w, 10000, Components::Direct, 1, 99 + i, techniques[i]);
    for (int c = 0; c < 3; ++c) {
      const double exact =
          singleScattering(glm::dvec3(o), glm::dvec3(w), glm::dvec3(light), 1.0, 0.05, k.sigmaS[c], k.g, 1.0, 3.0);
      for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(e[i].nonFinite, 0);
        EXPECT_NEAR(e[i].mean[c], exact, 4.0 * e[i].stderr_[c]) << names[i] << " channel " << c << " g " << k.g;
        std::printf("[ measured ] slab sigma_s %.1f g %.1f light %.2f m off: %-11s %.5f +- %.5f (quadrature %.5f)\n",
                    k.sigmaS[c], k.g, k.offset, names[i], e[i].mean[c], e[i].stderr_[c], exact);
      }
      // Forward scattering: MIS below both techniques alone (measured 0.64-0.69 of the better one). Isotropic with
      // the light 1 cm off: equiangular alone is nearly exact, MIS keeps free flights on the segment's far parts and
      // stays well below them (measured 1/28; 3.7 times equiangular's error).
      if (k.g > 0.0f)
        EXPECT_LT(e[0].stderr_[c], std::min(e[1].stderr_[c], e[2].stderr_[c])) << "channel " << c;
      else
        EXPECT_LT(e[0].stderr_[c], 0.1 * e[1].stderr_[c]) << "channel " << c;
    }
  }
}

// The point light in forward-scattering fog (assets/scenes/cornell-point-fog.gltf, docs/benchmarks.md): free flights
// drop scattering points next to the light, where next-event estimation's 1/d^2 makes fireflies. At 32^2 and 8 spp the
// 4x4-block relMSE between two seeds' images falls at least threefold with equiangular sampling, MIS and directions
// toward the light (measured 5.7x; 6x at 256^2, 256 spp in docs/benchmarks.md). The means are left to the slab above
// and the analytic tests: at this size the light's own pixel and the free flights' fireflies make them too noisy.
TEST(MediaDistanceMis, PointLightFogHasFewerFirefliesThanFreeFlightsAlone) {
  const auto offline = test::loadAssetScene("cornell-point-fog");
  const int size = 32, spp = 8;
  const Camera& camera = offline->scene().camera;
  auto render = [&](DistanceSampling techniques, uint64_t seed) {
    Image image(size, size);
    parallelFor(size, 2, [&](int64_t row, int) {
      const int y = static_cast<int>(row);
      for (int x = 0; x < size; ++x) {
        Rng rng(hashKey(seed, static_cast<uint64_t>(y * size + x)));
        glm::vec3 sum(0.0f);
        for (int i = 0; i < spp; ++i) {
          const glm::vec2 j = rng.next2D();
          const glm::vec3 dir = cameraRayDirection(camera, x + j.x, y + j.y, size, size);
          sum += referenceRadiance(offline->embree(), offline->lights(), camera.position, dir, 32, Components::All, rng,
                                   nullptr, techniques);
        }
        image.at(x, y) = sum / float(spp);
      }
    });
    return image;
  };
  double blockRelMse[2], mean[2];
  const DistanceSampling techniques[2] = {DistanceSampling::FreeFlight, DistanceSampling::Mis};
  for (int k = 0; k < 2; ++k) {
    const Image a = render(techniques[k], 1), b = render(techniques[k], 2);
    ASSERT_TRUE(allFinite(a) && allFinite(b));
    blockRelMse[k] = compareImages(blockAverage(a, 4), blockAverage(b, 4)).relMse;
    mean[k] = 0.5 * (meanLuminance(a) + meanLuminance(b));
  }
  std::printf(
      "[ measured ] point light in fog, 32^2 x 8 spp: two seeds' block relMSE %.5f (free flights) -> %.5f "
      "(MIS, %.1fx lower); mean %.4f -> %.4f\n",
      blockRelMse[0], blockRelMse[1], blockRelMse[0] / blockRelMse[1], mean[0], mean[1]);
  EXPECT_GT(blockRelMse[0], 3.0 * blockRelMse[1]);
}

// --- absorption only: exp(-sigma_a length) ----------------------------------------------------------------------

/// An emissive wall (Le = 1, albedo 0) at z = -5 facing +z, the camera at the origin looking down -z.
Scene emissiveWall(const Medium& medium) {
  Scene s;
  s.sourcePath = "emissive-wall";
  uint32_t m = test::addLambertMaterial(s, glm::vec3(0.0f), glm::vec3(1.0f));
  test::addQuad(s, {-10.0f, -10.0f, -5.0f}, {10.0f, -10.0f, -5.0f}, {10.0f, 10.0f, -5.0f}, {-10.0f, 10.0f, -5.0f}, m,
                {0, 0, 1});
  s.camera.position = glm::vec3(0.0f);
  s.camera.forward = glm::vec3(0.0f, 0.0f, -1.0f);
  s.camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
  s.media.push_back(medium);
  s.finalize();
  return s;
}

void expectAbsorption(const Medium& medium, float length, const char* what) {
  Scene scene = emissiveWall(medium);
  OfflineScene offline(scene);
  RayEstimate e = estimateRay(offline, glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, -1.0f), 100000, Components::All, 8, 5);
  EXPECT_EQ(e.nonFinite, 0) << what;
  for (int c = 0; c < 3; ++c) {
    const double exact = std::exp(-static_cast<double>(medium.sigmaA[c]) * length);
    EXPECT_NEAR(e.mean[c], exact, 4.0 * e.stderr_[c] + 1e-6) << what << " channel " << c;
    std::printf("%s channel %d: exp(-sigma_a l) %.5f, reference %.5f +- %.5f\n", what, c, exact, e.mean[c],
                e.stderr_[c]);
  }
  ProgressiveResult r = renderReference(offline, smallSettings(16, 4));
  EXPECT_EQ(r.nonFiniteSamples, 0u) << what;
  EXPECT_TRUE(allFinite(r.image)) << what;
  const glm::dvec3 mean = imageMean(r.image);
  for (int c = 0; c < 3; ++c) EXPECT_LE(mean[c], 1.0 + 1e-6) << what;
}

TEST(MediaReferenceAbsorption, CameraOutsideTheBox) {
  // z in [-3.5, -1.5]: 2 m of medium on the axis.
  expectAbsorption(
      boxMedium(glm::vec3(0.0f, 0.0f, -2.5f), glm::vec3(1.0f), glm::vec3(0.2f, 0.5f, 1.0f), glm::vec3(0.0f), 0.0f),
      2.0f, "camera outside");
}

TEST(MediaReferenceAbsorption, CameraInsideTheBox) {
  // z in [-2.5, 0.5] around the camera: 2.5 m of medium on the axis.
  expectAbsorption(boxMedium(glm::vec3(0.0f, 0.0f, -1.0f), glm::vec3(1.0f, 1.0f, 1.5f), glm::vec3(0.2f, 0.5f, 1.0f),
                             glm::vec3(0.0f), 0.0f),
                   2.5f, "camera inside");
}

// --- media that change nothing leave the image bit-identical ------------------------------------------------------

void expectSameImage(const Medium& medium, const char* what) {
  Scene plain = test::loadAssetScene("cornell-box")->scene();
  Scene withMedium = plain;
  withMedium.media.push_back(medium);
  OfflineScene a(plain), b(withMedium);
  Settings s = smallSettings(32, 4);
  ProgressiveResult ra = renderReference(a, s), rb = renderReference(b, s);
  ASSERT_EQ(ra.image.pixels.size(), rb.image.pixels.size());
  std::size_t differing = 0;
  for (std::size_t i = 0; i < ra.image.pixels.size(); ++i) differing += ra.image.pixels[i] != rb.image.pixels[i];
  EXPECT_EQ(differing, 0u) << what;
  EXPECT_GT(imageMean(ra.image).g, 0.0);
}

TEST(MediaReferenceConsistency, VacuumBoxIsBitIdentical) {
  const Bounds bounds = test::loadAssetScene("cornell-box")->scene().geometryBounds;
  expectSameImage(boxMedium(bounds.center(), 0.6f * bounds.extent(), glm::vec3(0.0f), glm::vec3(0.0f), 0.3f),
                  "vacuum box around the scene");
  expectSameImage(spaceMedium(glm::vec3(0.0f), glm::vec3(0.0f), 0.0f), "vacuum filling space");
}

TEST(MediaReferenceConsistency, MediumNoRayCrossesIsBitIdentical) {
  // A scattering box far outside the closed box: the media code paths run (transmittance on every shadow ray), but
  // no segment overlaps the box, so no free flight draws a number and every transmittance is exactly 1.
  const Bounds bounds = test::loadAssetScene("cornell-box")->scene().geometryBounds;
  const glm::vec3 far = bounds.upper + 10.0f * bounds.extent();
  expectSameImage(boxMedium(far, glm::vec3(0.1f), glm::vec3(1.0f), glm::vec3(1.0f), 0.0f), "box far away");
}

// --- extreme media ------------------------------------------------------------------------------------------------

Scene cornellWithMedium(const Medium& medium) {
  Scene scene = test::loadAssetScene("cornell-box")->scene();
  scene.media.push_back(medium);
  return scene;
}

Medium aroundCornell(const glm::vec3& sigmaA, const glm::vec3& sigmaS, float g) {
  const Bounds bounds = test::loadAssetScene("cornell-box")->scene().geometryBounds;
  return boxMedium(bounds.center(), 0.6f * bounds.extent(), sigmaA, sigmaS, g);
}

TEST(MediaReferenceExtreme, OpticallyHugeMediumIsFiniteDarkAndQuick) {
  for (const Medium& m :
       {aroundCornell(glm::vec3(1e6f), glm::vec3(0.0f), 0.0f), aroundCornell(glm::vec3(0.0f), glm::vec3(1e6f), 0.5f),
        spaceMedium(glm::vec3(1e6f), glm::vec3(1e6f), -0.3f)}) {
    Scene scene = cornellWithMedium(m);
    OfflineScene offline(scene);
    ProgressiveResult r = renderReference(offline, smallSettings(16, 4));
    EXPECT_EQ(r.nonFiniteSamples, 0u);
    EXPECT_TRUE(allFinite(r.image));
    const glm::dvec3 mean = imageMean(r.image);
    EXPECT_LT(std::max({mean.x, mean.y, mean.z}), 1e-6) << m.sigmaA.x << " " << m.sigmaS.x;
    EXPECT_LT(r.seconds, 60.0);
    std::printf("sigma_a %g sigma_s %g: mean (%g %g %g) in %.2f s\n", m.sigmaA.x, m.sigmaS.x, mean.x, mean.y, mean.z,
                r.seconds);
  }
}

TEST(MediaReferenceExtreme, ChannelWithoutInteractionIsFiniteAndUnattenuated) {
  // sigma_t = (0, s, s): red crosses the medium as vacuum, so its expectation is the media-free red. Compared on the
  // lit surfaces (the emitter and its edge left out, emitterMask): the emitter, exact in both renders and 55 % of the
  // Cornell box image's energy (reference_test.cpp), dilutes an error in the reflected red. Measured at 256 samples per
  // pixel over seeds 1-8: 0.994-1.000 (mean 0.9966, standard deviation 0.0020). Bound 2 %, below the 5 % of an error
  // in the reflected red, which fails it (checked: the lit pixels' red times 1.05 or 0.95).
  const Bounds bounds = test::loadAssetScene("cornell-box")->scene().geometryBounds;
  const float s = 2.0f / glm::length(bounds.extent());
  Scene scene = cornellWithMedium(aroundCornell(glm::vec3(0.0f), glm::vec3(0.0f, s, s), 0.3f));
  Scene plain = test::loadAssetScene("cornell-box")->scene();
  OfflineScene offline(scene), offlinePlain(plain);
  Settings settings = smallSettings(24, 256);
  ProgressiveResult r = renderReference(offline, settings);
  ProgressiveResult p = renderReference(offlinePlain, settings);
  EXPECT_EQ(r.nonFiniteSamples, 0u);
  EXPECT_TRUE(allFinite(r.image));
  const PixelMask emitters = emitterMask(offlinePlain.embree(), settings.width, settings.height);
  const ImageMetrics m = compareImagesExcluding(r.image, p.image, emitters);
  EXPECT_NEAR(m.energyRatio.x, 1.0, 0.02);
  std::printf("[ measured ] sigma_t (0 %g %g), emitters left out: red %.4f of the render without the medium (green "
              "%.4f, blue %.4f)\n",
              s, s, m.energyRatio.x, m.energyRatio.y, m.energyRatio.z);
}

// --- a directional light in a medium that fills all space ---------------------------------------------------------

TEST(MediaReferenceDirectional, AbsorbingSpaceAttenuatesFromTheEmissionDisk) {
  const glm::vec3 travel = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
  const float irradiance = 3.0f, albedo = 0.5f, sigmaA = 0.3f;
  Scene scene = test::makePlaneUnderDirectionalLight(2.0f, travel, irradiance, albedo);
  scene.media.push_back(spaceMedium(glm::vec3(sigmaA), glm::vec3(0.0f), 0.0f));
  OfflineScene offline(scene);
  // The plane's centre seen from straight above at height 2: (a / pi) E cos * T(disk -> x) * T(x -> camera).
  const glm::vec3 x(0.0f), origin(0.0f, 2.0f, 0.0f);
  const float dDisk = offline.lights().directionalMediumDistance(scene.punctualLights[0], x);
  const float radius = 0.5f * scene.geometryBounds.diagonal();
  EXPECT_GE(dDisk, radius);  // the disk lies outside the scene's bounding sphere
  EXPECT_LE(dDisk, 1.1f * radius);
  const double exact = albedo / M_PI * irradiance * -travel.y * std::exp(-sigmaA * (dDisk + 2.0));
  RayEstimate e = estimateRay(offline, origin, glm::vec3(0.0f, -1.0f, 0.0f), 40000, Components::All, 8, 17);
  EXPECT_EQ(e.nonFinite, 0);
  EXPECT_NEAR(e.mean.g, exact, 4.0 * e.stderr_.g + 1e-6);
  std::printf("directional through absorbing space: exact %.5f, reference %.5f +- %.5f (disk at %.3f)\n", exact,
              e.mean.g, e.stderr_.g, dDisk);
}

TEST(MediaReferenceDirectional, ScatteringSpaceRendersFinite) {
  Scene scene = test::makePlaneUnderDirectionalLight(2.0f, glm::vec3(0.3f, -1.0f, 0.2f), 3.0f, 0.5f);
  scene.media.push_back(spaceMedium(glm::vec3(0.05f), glm::vec3(0.1f, 0.3f, 0.5f), 0.4f));
  OfflineScene offline(scene);
  ProgressiveResult r = renderReference(offline, smallSettings(16, 8));
  EXPECT_EQ(r.nonFiniteSamples, 0u);
  EXPECT_TRUE(allFinite(r.image));
  const glm::dvec3 mean = imageMean(r.image);
  EXPECT_GT(mean.g, 0.0);
  std::printf("directional in scattering space: mean (%.4f %.4f %.4f)\n", mean.x, mean.y, mean.z);
}

}  // namespace
}  // namespace vplab
