// Bidirectional instant radiosity (Segovia et al. 2006; docs/methods.md, "Bidirectional instant radiosity").
//
// A pool of candidate VPLs from two strategies, then exactly vplCount of them chosen in proportion to importance:
//   light strategy   n_L light paths, a candidate at every bounce (flux alpha / n_L);
//   camera strategy  n_C samples: a camera point x1_k (stratified over the importance points), a BRDF-sampled
//                    direction to x2, and a light sample y seen from x2: a first-bounce candidate at x2 lit by y.
// Both strategies make first-bounce candidates (a pair y -> x2), so those are weighted by the balance heuristic:
//   p_L(x2 | y) = pdf_emit(y -> x2) cos2 / d^2                        (light tracing from the same point y)
//   p_C(x2)     = 1/M sum_k pdf_brdf(x1_k -> x2) cos2 / d_k^2 V_k   (all camera samples together: n_C p_C)
//   flux        = Le cos2 / pdf_light(y -> x2) / (n_L p_L + n_C p_C)  (camera)
//                 alpha p_L / (n_L p_L + n_C p_C)                    (light; later bounces keep alpha / n_L)
// The point y is drawn with the same density by both (light by power, point uniform on its area), so it cancels.
// Resampling: inclusion probabilities pi_i = min(1, c w_i) with sum pi_i = vplCount, w_i = importance / mean +
// epsilon flux / mean, each candidate kept with its pi_i; a kept candidate's flux is divided by pi_i
// (Horvitz-Thompson), so the expected VPL sum is the pool's, which is unbiased.

#include "renderer/scene/brdf_params.h"
#include "renderer/vpl/generation_detail.h"
#include "renderer/vpl/vpl_importance.h"

#include <algorithm>
#include <cmath>

namespace vplab {

namespace {

constexpr uint64_t kTagBirLight = 0x4249524cull;
constexpr uint64_t kTagBirCamera = 0x42495243ull;
constexpr uint64_t kTagBirSelect = 0x42495253ull;

/// p_C(x2) without the sample count: the mean over the camera points of the area density with which a BRDF sample
/// from x1_k reaches x2 first.
double cameraAreaPdf(const EmbreeScene& embree, const std::vector<ShadingPoint>& points, const Vpl& x2) {
  std::vector<ShadowRay> rays;
  std::vector<double> pdfs;
  rays.reserve(points.size());
  pdfs.reserve(points.size());
  for (const ShadingPoint& sp : points) {
    glm::vec3 d = x2.position - sp.hit.position;
    float d2 = glm::dot(d, d);
    if (!(d2 > 0.0f)) continue;
    glm::vec3 w = d / std::sqrt(d2);
    float cos2 = -glm::dot(x2.geometricNormal, w);
    if (glm::dot(sp.hit.geometricNormal, w) <= 0.0f || cos2 <= 0.0f) continue;
    float pdfW = brdfPdf(sp.brdf, sp.hit.shadingNormal, sp.wo, w);
    if (!(pdfW > 0.0f)) continue;
    rays.push_back(embree.shadowRayBetween(sp.hit.position, sp.hit.geometricNormal, x2.position, x2.geometricNormal));
    pdfs.push_back(static_cast<double>(pdfW) * cos2 / d2);
  }
  std::vector<uint8_t> blocked(rays.size());
  if (!rays.empty()) embree.occludedBatch(rays.data(), blocked.data(), rays.size());
  double sum = 0.0;
  for (std::size_t i = 0; i < rays.size(); ++i)
    if (!blocked[i]) sum += pdfs[i];
  return points.empty() ? 0.0 : sum / static_cast<double>(points.size());
}

/// One camera sample from x1: BRDF direction, light sample. Returns false when it makes no candidate. `out`
/// receives the candidate with flux Le cos2 / pdf_light (not yet divided by the combined density) and `pL` the
/// light strategy's density p_L(x2 | y).
bool cameraCandidate(const GenerationContext& ctx, const ShadingPoint& x1, Rng& rng, Vpl& out, double& pL) {
  glm::vec3 u(rng.next1D(), rng.next1D(), rng.next1D());
  float uLight = rng.next1D();
  glm::vec2 uPoint(rng.next1D(), rng.next1D());
  BrdfSample bs = sampleBrdf(x1.brdf, x1.hit.shadingNormal, x1.wo, u);
  if (!bs.valid() || glm::dot(x1.hit.geometricNormal, bs.wi) <= 0.0f) return false;
  std::optional<SurfaceHit> hit =
      ctx.embree.intersect(ctx.embree.offsetOrigin(x1.hit.position, x1.hit.geometricNormal, bs.wi), bs.wi);
  if (!hit || glm::dot(hit->geometricNormal, -bs.wi) <= 0.0f) return false;
  LightSampleLi li = ctx.lights.sampleLi(hit->position, uLight, uPoint);
  // Only lights that light tracing could also reach with a direction density: the pair then has both densities.
  if (!li.valid() || !(li.emissionPdfDirection > 0.0f)) return false;
  float cos2 = glm::dot(hit->geometricNormal, li.wi);
  if (cos2 <= 0.0f) return false;
  glm::vec3 le = li.radiance;
  if (!(std::max({le.r, le.g, le.b}) > 0.0f)) return false;
  ShadowRay ray = li.isDelta
                      ? ShadowRay{ctx.embree.offsetOrigin(hit->position, hit->geometricNormal, li.wi), li.wi,
                                  li.distance * (1.0f - 1e-4f)}
                      : ctx.embree.shadowRayBetween(hit->position, hit->geometricNormal, li.position, li.normal);
  uint8_t blocked = 0;
  ctx.embree.occludedBatch(&ray, &blocked, 1);
  if (blocked) return false;
  out = Vpl{};
  out.position = hit->position;
  out.normal = hit->shadingNormal;
  out.geometricNormal = hit->geometricNormal;
  out.incoming = li.wi;
  out.flux = le * (cos2 / li.pdf);
  out.uv = hit->uv;
  out.material = hit->material;
  out.bounce = 1;
  pL = static_cast<double>(li.emissionPdfDirection) * cos2 / (li.distance * li.distance);
  return true;
}

}  // namespace

std::vector<double> inclusionProbabilities(const std::vector<double>& w, std::size_t n) {
  std::vector<double> pi(w.size(), 0.0);
  std::vector<bool> capped(w.size(), false);
  std::size_t positive = 0;
  for (double x : w) positive += x > 0.0 ? 1 : 0;
  if (positive <= n) {
    for (std::size_t i = 0; i < w.size(); ++i) pi[i] = w[i] > 0.0 ? 1.0 : 0.0;
    return pi;
  }
  // Capping one weight raises c for the rest, so iterate until no new weight reaches 1 (at most n rounds).
  std::size_t cappedCount = 0;
  for (;;) {
    double free = 0.0;
    for (std::size_t i = 0; i < w.size(); ++i)
      if (!capped[i]) free += w[i];
    const double c = static_cast<double>(n - cappedCount) / free;
    bool changed = false;
    for (std::size_t i = 0; i < w.size(); ++i)
      if (!capped[i] && c * w[i] >= 1.0) {
        capped[i] = true;
        ++cappedCount;
        changed = true;
      }
    if (!changed) {
      for (std::size_t i = 0; i < w.size(); ++i) pi[i] = capped[i] ? 1.0 : c * w[i];
      return pi;
    }
  }
}

VplSet generateBidirectional(const GenerationContext& ctx) {
  const Settings& s = ctx.settings;
  ImportanceEstimator importance(ctx.offline, s);
  if (importance.empty()) return fallBackToLightTracing(ctx, "bidirectional: no importance point sees a surface");
  const std::vector<ShadingPoint>& points = importance.points();
  VplSet set;
  const double perPath = candidatesPerLightPath(ctx);
  if (!(perPath > 0.0)) return set;  // no light path reaches a surface: there is no indirect light
  const std::size_t n = static_cast<std::size_t>(s.vplCount);
  const double pool = static_cast<double>(n) * std::max(1, s.birCandidateFactor);
  const int64_t nL = std::max<int64_t>(1, static_cast<int64_t>(std::ceil(pool * s.birLightShare / perPath)));
  const int64_t nC = static_cast<int64_t>(std::llround(pool * (1.0 - s.birLightShare)));

  // The light strategy.
  std::vector<float> emitPdf;
  std::vector<uint32_t> perPathCount;
  std::vector<Vpl> candidates = traceLightPaths(ctx, nL, kTagBirLight, &perPathCount, &emitPdf);
  const std::size_t lightCount = candidates.size();
  // Each candidate's selection number is keyed by where it comes from (light path and place on it, or camera
  // sample), so a small scene change keeps most selections.
  std::vector<uint64_t> keys;
  keys.reserve(lightCount);
  for (std::size_t j = 0; j < perPathCount.size(); ++j)
    for (uint32_t k = 0; k < perPathCount[j]; ++k) keys.push_back(hashKey(j, k));
  std::vector<double> pL(emitPdf.begin(), emitPdf.end());

  // The camera strategy: sample c uses camera point floor((c + u) M / n_C), so every point gets n_C / M samples
  // and all camera samples together have the density n_C p_C.
  const std::size_t m = points.size();
  std::vector<Vpl> camera(static_cast<std::size_t>(nC));
  std::vector<double> cameraPL(static_cast<std::size_t>(nC), 0.0);
  std::vector<uint8_t> made(static_cast<std::size_t>(nC), 0);
  parallelFor(
      nC, s.threads,
      [&](int64_t c, int) {
        Rng rng(hashKey(hashKey(s.seed, kTagBirCamera), static_cast<uint64_t>(c)));
        double stratum = (static_cast<double>(c) + rng.next1D()) * static_cast<double>(m) / static_cast<double>(nC);
        std::size_t k = std::min(m - 1, static_cast<std::size_t>(stratum));
        std::size_t i = static_cast<std::size_t>(c);
        made[i] = cameraCandidate(ctx, points[k], rng, camera[i], cameraPL[i]) ? 1 : 0;
      },
      ctx.control);
  for (std::size_t i = 0; i < camera.size(); ++i)
    if (made[i]) {
      candidates.push_back(camera[i]);
      pL.push_back(cameraPL[i]);
      keys.push_back(hashKey(i, 0, kTagBirCamera));
    }
  set.stats.cameraCandidates = candidates.size() - lightCount;

  // Balance-heuristic weights of the first-bounce candidates (both strategies); later bounces are light tracing's.
  const double invNL = 1.0 / static_cast<double>(nL);
  parallelFor(
      static_cast<int64_t>(candidates.size()), s.threads,
      [&](int64_t ii, int) {
        std::size_t i = static_cast<std::size_t>(ii);
        Vpl& v = candidates[i];
        const bool fromCamera = i >= lightCount;
        if (!fromCamera && !(v.bounce == 1 && pL[i] > 0.0)) {
          v.flux *= static_cast<float>(invNL);
          return;
        }
        const double pC = nC > 0 ? cameraAreaPdf(ctx.embree, points, v) : 0.0;
        const double combined = static_cast<double>(nL) * pL[i] + static_cast<double>(nC) * pC;
        const double scale = fromCamera ? (combined > 0.0 ? 1.0 / combined : 0.0)
                                        : (combined > 0.0 ? pL[i] / combined : invNL);
        v.flux *= static_cast<float>(scale);
      },
      ctx.control);

  // Resampling weights: importance relative to its mean plus epsilon times flux relative to its mean.
  std::vector<double> imp(candidates.size()), flux(candidates.size());
  parallelFor(
      static_cast<int64_t>(candidates.size()), s.threads,
      [&](int64_t i, int) {
        const Vpl& v = candidates[static_cast<std::size_t>(i)];
        imp[static_cast<std::size_t>(i)] = importance(v);
        flux[static_cast<std::size_t>(i)] = std::max(0.0f, luminance(v.flux));
      },
      ctx.control);
  double meanImp = 0.0, meanFlux = 0.0;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    meanImp += imp[i];
    meanFlux += flux[i];
  }
  if (!(meanImp > 0.0))
    return fallBackToLightTracing(ctx, "bidirectional: no candidate lights an importance point");
  meanImp /= static_cast<double>(candidates.size());
  meanFlux /= static_cast<double>(candidates.size());
  std::vector<double> w(candidates.size());
  for (std::size_t i = 0; i < w.size(); ++i)
    w[i] = imp[i] / meanImp + (meanFlux > 0.0 ? s.birEpsilon * flux[i] / meanFlux : 0.0);
  std::vector<double> pi = inclusionProbabilities(w, n);

  // Each candidate is kept with probability pi_i by its own keyed random number (Poisson sampling: the count is
  // vplCount in expectation; a systematic sample would hit it exactly but flip many selections when any weight
  // before them changes, which makes a moving light flicker).
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    Rng select(hashKey(s.seed, keys[i], kTagBirSelect));
    keepWithProbability(candidates[i], pi[i], select.next1D(), set);
  }
  set.stats.candidates = candidates.size();
  set.stats.pathsTraced = static_cast<uint64_t>(nL);
  return set;
}

}  // namespace vplab
