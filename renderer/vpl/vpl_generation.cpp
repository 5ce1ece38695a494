#include "renderer/vpl/vpl_generation.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <optional>

#include "renderer/offline/spectral_mis.h"
#include "renderer/scene/brdf_params.h"
#include "renderer/vpl/generation_detail.h"
#include "renderer/vpl/vpl_importance.h"

namespace vplab {

namespace {

// Stream tags: each kind of decision gets its own random stream, so adding one never shifts another.
constexpr uint64_t kTagHaltonOffset = 0x48414c544f4eull;
constexpr uint64_t kTagPathTail = 0x5041544854ull;

constexpr uint64_t kTagPilot = 0x50494c4f54ull;
constexpr uint64_t kTagRejectionPilot = 0x524a5049ull;
constexpr uint64_t kTagAccept = 0x414343455054ull;

constexpr std::array<uint32_t, kHaltonDims> kHaltonBases = {2, 3, 5, 7, 11, 13, 17, 19};
/// Light paths per parallel work item (VPLs are concatenated in path order, so the set is thread-count independent).
constexpr int64_t kPathsPerItem = 128;

double meanOf(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

double standardDeviation(const std::vector<double>& v, double mean) {
  if (v.size() < 2) return 0.0;
  double s = 0.0;
  for (double x : v) s += (x - mean) * (x - mean);
  return std::sqrt(s / static_cast<double>(v.size() - 1));
}

/// Mean of p_i = min(phi_i / phiV + epsilon, 1) over the pilot.
double meanAcceptance(const std::vector<double>& phi, double phiV, double epsilon) {
  double sum = 0.0;
  for (double p : phi) sum += std::min(p / phiV + epsilon, 1.0);
  return phi.empty() ? 1.0 : sum / static_cast<double>(phi.size());
}

/// Light tracing with rejection of unimportant VPLs (Georgiev & Slusallek 2010; docs/methods.md, "Rejection").
VplSet traceWithRejection(const GenerationContext& ctx, const ImportanceEstimator& importance) {
  const Settings& settings = ctx.settings;
  VplSet set;
  // Step 1, the pilot: Phi_v = mean importance of pilot VPLs from stratified paths of their own stream, measured
  // at the same fixed points as the main pass.
  const std::size_t wanted = static_cast<std::size_t>(std::max(1, settings.rejectionPilotVpls));
  const double perPath = candidatesPerLightPath(ctx);
  if (!(perPath > 0.0)) return set;
  std::vector<Vpl> pilot;
  int64_t pilotPaths = static_cast<int64_t>(std::ceil(1.1 * static_cast<double>(wanted) / perPath));
  for (int attempt = 0; attempt < 4 && pilot.size() < wanted; ++attempt, pilotPaths *= 2)
    pilot = traceLightPaths(ctx, pilotPaths, kTagRejectionPilot);
  pilot.resize(std::min(pilot.size(), wanted));
  if (pilot.empty()) return set;
  std::vector<double> phi(pilot.size());
  parallelFor(static_cast<int64_t>(pilot.size()), settings.threads, [&](int64_t i, int) {
    phi[static_cast<std::size_t>(i)] = importance(pilot[static_cast<std::size_t>(i)]);
  });
  const double phiV = meanOf(phi);
  if (!(phiV > 0.0)) return fallBackToLightTracing(ctx, "rejection: no pilot VPL lights an importance point");
  const double eps = settings.rejectionEpsilon;
  const double accept = meanAcceptance(phi, phiV, eps);
  // The spread to expect between seeds: Phi_v's standard error moves every p_i, and the mean of p_i has its own.
  const double phiError = standardDeviation(phi, phiV) / std::sqrt(static_cast<double>(phi.size()));
  const double fromPhiV = 0.5 * std::abs(meanAcceptance(phi, std::max(phiV - phiError, 1e-30), eps) -
                                         meanAcceptance(phi, phiV + phiError, eps));
  std::vector<double> p(phi.size());
  for (std::size_t i = 0; i < phi.size(); ++i) p[i] = std::min(phi[i] / phiV + eps, 1.0);
  const double fromMean = standardDeviation(p, accept) / std::sqrt(static_cast<double>(p.size()));
  set.stats.predictedAcceptance = accept;
  set.stats.acceptanceSpread = std::sqrt(fromPhiV * fromPhiV + fromMean * fromMean);

  // Plan N_paths before tracing so that it does not depend on the paths it normalises. The candidate cap limits
  // the expected candidates to rejectionMaxCandidateFactor x vplCount.
  const double maxCandidates =
      static_cast<double>(settings.rejectionMaxCandidateFactor) * static_cast<double>(settings.vplCount);
  double plannedPaths = std::ceil(settings.vplCount / (perPath * accept));
  if (plannedPaths * perPath > maxCandidates) {
    plannedPaths = std::max(1.0, std::floor(maxCandidates / perPath));
    set.stats.candidateCapReached = true;
  }
  const int64_t paths = static_cast<int64_t>(std::clamp(plannedPaths, 1.0, 1.0e9));

  // Step 2: accept each candidate with p_i = min(Phi_i / Phi_v + epsilon, 1) and divide its flux by p_i (Russian
  // roulette on the expected contribution to the image). The decision's random number is keyed by the path and
  // the candidate's place on it, so a small scene change keeps most decisions.
  std::vector<uint32_t> perPathCount;
  std::vector<Vpl> candidates = traceLightPaths(ctx, paths, kTagMainPaths, &perPathCount);
  std::vector<double> pAccept(candidates.size());
  parallelFor(
      static_cast<int64_t>(candidates.size()), settings.threads,
      [&](int64_t i, int) {
        pAccept[static_cast<std::size_t>(i)] =
            std::min(importance(candidates[static_cast<std::size_t>(i)]) / phiV + eps, 1.0);
      },
      ctx.control);
  const float invPaths = 1.0f / static_cast<float>(paths);
  std::size_t c = 0;
  for (std::size_t j = 0; j < perPathCount.size(); ++j) {
    Rng acceptRng(hashKey(settings.seed, j, kTagAccept));
    for (uint32_t k = 0; k < perPathCount[j]; ++k, ++c) {
      Vpl v = candidates[c];
      v.flux *= invPaths;
      keepWithProbability(v, pAccept[c], acceptRng.next1D(), set);
    }
  }
  set.stats.candidates = candidates.size();
  set.stats.pathsTraced = static_cast<uint64_t>(paths);
  return set;
}

/// Plain light tracing: N_paths planned from the pilot's candidates per path, every candidate kept.
VplSet tracePlain(const GenerationContext& ctx) {
  VplSet set;
  const double perPath = candidatesPerLightPath(ctx);
  const double planned = perPath > 0.0 ? std::ceil(ctx.settings.vplCount / perPath) : ctx.settings.vplCount;
  const int64_t paths = static_cast<int64_t>(std::clamp(planned, 1.0, 1.0e9));
  // The same paths' media segments are the virtual ray lights (scenes with media only).
  set.vpls = traceLightPaths(ctx, paths, kTagMainPaths, nullptr, nullptr,
                             ctx.scene.hasMedia() ? &set.vrls : nullptr);
  const float invPaths = 1.0f / static_cast<float>(paths);
  for (Vpl& v : set.vpls) v.flux *= invPaths;
  for (Vrl& v : set.vrls) v.flux *= invPaths;
  set.stats.candidates = set.vpls.size();
  set.stats.pathsTraced = static_cast<uint64_t>(paths);
  return set;
}

}  // namespace

uint64_t streamSeed(uint32_t seed, uint64_t tag) { return tag == kTagMainPaths ? seed : hashKey(seed, tag); }

std::array<float, kHaltonDims> haltonOffsets(uint32_t seed, uint64_t tag) {
  std::array<float, kHaltonDims> offsets;
  for (int d = 0; d < kHaltonDims; ++d)
    offsets[d] =
        static_cast<float>(hashKey(streamSeed(seed, tag), static_cast<uint64_t>(d), kTagHaltonOffset) >> 40) *
        0x1p-24f;
  return offsets;
}

float HaltonPathSampler::next() {
  if (dim_ < kHaltonDims) {
    float u = rotateUnit(radicalInverse(kHaltonBases[dim_], index_), offsets_[dim_]);
    ++dim_;
    return u;
  }
  ++dim_;
  return rng_.next1D();
}

EmissionSample sampleLightEmission(const LightSampler& lights, RandomSource& random) {
  // The sampler draws the light by power, a point uniform on its area and a cosine direction; weight =
  // Le cos / (p_light pdf_A pdf_dir) = alpha_0 (before the 1/N_paths normalisation). A directional light starts on
  // a disk covering the scene, pdf_A = 1 / (pi R^2), weight E pi R^2 / p_light (LightSampler::sampleEmission,
  // docs/methods.md "Directional lights").
  float uLight = random.next();
  glm::vec2 uPoint(random.next(), random.next());
  glm::vec2 uDir(random.next(), random.next());
  return lights.sampleEmission(uLight, uPoint, uDir);
}

void traceLightPath(const Scene& scene, const EmbreeScene& embree, const LightSampler& lights, int maxBounces,
                    RandomSource& random, std::vector<Vpl>& out, std::vector<float>* emissionAreaPdf,
                    std::vector<Vrl>* vrls) {
  // Step 1: emission sample.
  EmissionSample e = sampleLightEmission(lights, random);
  if (!e.valid) return;
  glm::vec3 alpha = e.weight;
  const float alpha0Max = std::max({alpha.r, alpha.g, alpha.b});
  if (!(alpha0Max > 0.0f)) return;
  glm::vec3 origin = glm::dot(e.normal, e.normal) > 0.0f ? embree.offsetOrigin(e.position, e.normal, e.direction)
                                                         : e.position;
  glm::vec3 dir = e.direction;
  // Free flights draw their two numbers only on segments that cross a medium (EmbreeScene::traceSegment), so paths
  // in a scene without media draw exactly the numbers they always did; through chromatic media every flight of the
  // path samples one channel, weighted by spectral MIS over the whole path (bounded flux, no fireflies).
  PathSpectralMis spectral;
  auto next2D = [&random]() {
    float a = random.next();
    return glm::vec2(a, random.next());
  };
  auto draw = [&]() { return spectral.draw(next2D()); };
  std::vector<MediumInterval> intervals;

  for (int bounce = 1; bounce <= maxBounces; ++bounce) {
    // Step 2: find the next surface or scattering event. The vertex on the light is not a VPL: direct light is
    // computed exactly.
    Segment segment = embree.traceSegment(origin, dir, kInfinity, draw);
    if (segment.crossedMedium && vrls) {
      // The segment's media parts are virtual ray lights, up to the surface whatever the free flight sampled.
      mediumIntervals(scene.media, origin, dir, segment.surfaceDistance, intervals);
      for (const MediumInterval& i : intervals)
        if (std::isfinite(i.t1))
          vrls->push_back({origin, dir, i.t0, i.t1, alpha, i.medium, static_cast<uint32_t>(bounce - 1)});
    }
    if (segment.end == Segment::End::Escape) return;
    // Free-flight weight: T sigma_s / pdf at a scattering event, T / P(no event) at a surface (docs/theory.md §16).
    if (segment.crossedMedium) spectral.apply(segment, alpha);
    glm::vec3 wIn = -dir;

    if (segment.scattered()) {
      // Step 3': a medium VPL (docs/theory.md §17): the light that scattered here, reflected later by the phase
      // function from wIn.
      Vpl v;
      v.position = segment.position;
      v.incoming = wIn;
      v.flux = alpha;
      v.inMedium = true;
      v.medium = segment.medium;
      v.bounce = static_cast<uint32_t>(bounce);
      out.push_back(v);
      if (emissionAreaPdf) emissionAreaPdf->push_back(0.0f);
      if (bounce == maxBounces) return;
      // Step 4': continue by phase-function sampling (f_p / pdf = 1: alpha is unchanged). HG is symmetric in its two
      // directions, so sampling "wi" around wIn draws the outgoing direction with density f_p(out, wIn).
      glm::vec2 u = next2D();
      dir = samplePhaseHG(wIn, scene.media[segment.medium].g, u).wi;
      origin = segment.position;
    } else {
      const SurfaceHit* hit = &*segment.hit;
      // One-sided surfaces absorb light arriving at their back.
      if (glm::dot(hit->geometricNormal, wIn) <= 0.0f) return;

      // Step 3: store the VPL: the light that arrived here with throughput alpha, reflected later by f(x2).
      Vpl v;
      v.position = hit->position;
      v.normal = hit->shadingNormal;
      v.geometricNormal = hit->geometricNormal;
      v.incoming = wIn;
      v.flux = alpha;
      v.uv = hit->uv;
      v.material = hit->material;
      v.bounce = static_cast<uint32_t>(bounce);
      out.push_back(v);
      if (emissionAreaPdf) {
        glm::vec3 d = hit->position - e.position;
        float d2 = glm::dot(d, d);
        emissionAreaPdf->push_back(bounce == 1 && d2 > 0.0f && !segment.crossedMedium
                                       ? e.pdfDirection * glm::dot(hit->geometricNormal, wIn) / d2
                                       : 0.0f);
      }
      if (bounce == maxBounces) return;

      // Step 4: continue by BRDF sampling, alpha *= f cos / pdf (the three numbers are drawn whatever happens).
      glm::vec3 u(random.next(), random.next(), random.next());
      BrdfParams params = brdfParamsAt(scene, hit->material, hit->uv);
      BrdfSample bs = sampleBrdf(params, hit->shadingNormal, wIn, u);
      if (!bs.valid() || glm::dot(hit->geometricNormal, bs.wi) <= 0.0f) return;
      float cosI = glm::dot(hit->shadingNormal, bs.wi);
      if (!(cosI > 0.0f)) return;
      alpha *= bs.f * (cosI / bs.pdf);
      origin = embree.offsetOrigin(hit->position, hit->geometricNormal, bs.wi);
      dir = bs.wi;
    }

    // Step 5: Russian roulette on the throughput relative to alpha_0: survivors are scaled back up, so VPLs carry
    // roughly equal flux (Keller 1997) and dark paths end early.
    float uRr = random.next();
    float survive = std::min(1.0f, std::max({alpha.r, alpha.g, alpha.b}) / alpha0Max);
    if (!(survive > 0.0f) || uRr >= survive) return;
    alpha /= survive;
  }
}

std::vector<Vpl> traceLightPaths(const GenerationContext& ctx, int64_t paths, uint64_t tag,
                                 std::vector<uint32_t>* pathCandidateCount, std::vector<float>* emissionAreaPdf,
                                 std::vector<Vrl>* vrls) {
  const std::array<float, kHaltonDims> offsets = haltonOffsets(ctx.settings.seed, tag);
  const int maxBounces = std::max(1, ctx.settings.vplMaxBounces);
  const int64_t items = (paths + kPathsPerItem - 1) / kPathsPerItem;
  std::vector<std::vector<Vpl>> chunks(static_cast<std::size_t>(items));
  std::vector<std::vector<float>> pdfChunks(emissionAreaPdf ? static_cast<std::size_t>(items) : 0);
  std::vector<std::vector<Vrl>> vrlChunks(vrls ? static_cast<std::size_t>(items) : 0);
  std::vector<uint32_t> counts(static_cast<std::size_t>(std::max<int64_t>(paths, 0)), 0);
  parallelFor(
      items, ctx.settings.threads,
      [&](int64_t item, int) {
        std::vector<Vpl>& chunk = chunks[static_cast<std::size_t>(item)];
        const int64_t end = std::min(paths, (item + 1) * kPathsPerItem);
        for (int64_t j = item * kPathsPerItem; j < end; ++j) {
          std::size_t before = chunk.size();
          HaltonPathSampler sampler(static_cast<uint64_t>(j), offsets,
                                    hashKey(streamSeed(ctx.settings.seed, tag), static_cast<uint64_t>(j), kTagPathTail));
          traceLightPath(ctx.scene, ctx.embree, ctx.lights, maxBounces, sampler, chunk,
                         emissionAreaPdf ? &pdfChunks[static_cast<std::size_t>(item)] : nullptr,
                         vrls ? &vrlChunks[static_cast<std::size_t>(item)] : nullptr);
          counts[static_cast<std::size_t>(j)] = static_cast<uint32_t>(chunk.size() - before);
        }
      },
      ctx.control);
  std::vector<Vpl> out;
  for (std::vector<Vpl>& c : chunks) out.insert(out.end(), c.begin(), c.end());
  if (pathCandidateCount) *pathCandidateCount = std::move(counts);
  if (emissionAreaPdf) {
    emissionAreaPdf->clear();
    for (std::vector<float>& c : pdfChunks) emissionAreaPdf->insert(emissionAreaPdf->end(), c.begin(), c.end());
  }
  if (vrls) {
    vrls->clear();
    for (std::vector<Vrl>& c : vrlChunks) vrls->insert(vrls->end(), c.begin(), c.end());
  }
  return out;
}

double candidatesPerLightPath(const GenerationContext& ctx) {
  // Plain PCG streams, independent of every Halton-driven set of paths.
  std::vector<uint64_t> counts(kVplPilotPaths);
  parallelFor(kVplPilotPaths, ctx.settings.threads, [&](int64_t p, int) {
    class Stream : public RandomSource {
     public:
      explicit Stream(uint64_t key) : rng_(key) {}
      float next() override { return rng_.next1D(); }

     private:
      Rng rng_;
    } stream(hashKey(ctx.settings.seed, static_cast<uint64_t>(p), kTagPilot));
    std::vector<Vpl> vpls;
    traceLightPath(ctx.scene, ctx.embree, ctx.lights, std::max(1, ctx.settings.vplMaxBounces), stream, vpls);
    counts[static_cast<std::size_t>(p)] = vpls.size();
  });
  uint64_t total = 0;
  for (uint64_t c : counts) total += c;
  return static_cast<double>(total) / static_cast<double>(kVplPilotPaths);
}

VplSet fallBackToLightTracing(const GenerationContext& ctx, const std::string& reason) {
  VplSet set = tracePlain(ctx);
  set.stats.generation = VplGeneration::Light;
  set.stats.warnings.push_back(reason + "; fell back to plain light tracing");
  return set;
}

VplSet generateLightTraced(const GenerationContext& ctx) {
  if (!ctx.settings.rejection) return tracePlain(ctx);
  ImportanceEstimator importance(ctx.offline, ctx.settings);
  if (importance.empty()) return fallBackToLightTracing(ctx, "rejection: no importance point sees a surface");
  return traceWithRejection(ctx, importance);
}

std::vector<float> vslRadii(const std::vector<Vpl>& vpls, const Settings& settings, float sceneDiagonal) {
  std::vector<float> radii(vpls.size(), settings.vslRadius);
  if (!settings.vslRadiusFromDensity || vpls.empty()) return radii;
  const int k = kVslDensityNeighbour;
  const float fallback = sceneDiagonal > 0.0f ? sceneDiagonal : 1.0f;
  // Brute-force k-th nearest neighbour (O(N^2), parallel): exact and simple; N is at most a few tens of thousands.
  parallelFor(static_cast<int64_t>(vpls.size()), settings.threads, [&](int64_t i, int) {
    std::array<float, kVslDensityNeighbour> best;
    best.fill(fallback * fallback);
    for (std::size_t j = 0; j < vpls.size(); ++j) {
      if (static_cast<int64_t>(j) == i) continue;
      glm::vec3 d = vpls[j].position - vpls[static_cast<std::size_t>(i)].position;
      float d2 = glm::dot(d, d);
      if (d2 >= best[k - 1]) continue;
      int pos = k - 1;
      while (pos > 0 && best[pos - 1] > d2) {
        best[pos] = best[pos - 1];
        --pos;
      }
      best[pos] = d2;
    }
    radii[static_cast<std::size_t>(i)] = settings.vslRadius * std::sqrt(best[k - 1]);
  });
  return radii;
}

VplSet generateVpls(const OfflineScene& offline, const Settings& settings, RenderControl* control) {
  const Scene& scene = offline.scene();
  const LightSampler& lights = offline.lights();
  const auto start = std::chrono::steady_clock::now();
  VplSet set;
  set.stats.generation = settings.generation;
  if (settings.vplCount > 0 && !lights.empty() && !scene.triangles.empty()) {
    GenerationContext ctx{offline, scene, offline.embree(), lights, settings, control};
    if (scene.hasMedia() && (settings.generation != VplGeneration::Light || settings.rejection)) {
      // The importance of a VPL (rejection, bidirectional resampling, the Metropolis target) is measured at surface
      // points with surface transfer only: in media it would be wrong, so media scenes are light traced.
      set = fallBackToLightTracing(ctx, "the scene has participating media, which only plain light tracing supports");
    } else {
      set = generationMethod(settings.generation).generate(ctx);
    }
    if (set.stats.warnings.empty()) set.stats.generation = settings.generation;
  }
  set.stats.accepted = set.vpls.size();
  set.stats.acceptanceRate =
      set.stats.candidates > 0 ? static_cast<double>(set.stats.accepted) / set.stats.candidates : 1.0;
  std::vector<float> radii = vslRadii(set.vpls, settings, scene.bounds.diagonal());
  for (std::size_t i = 0; i < set.vpls.size(); ++i) set.vpls[i].radius = radii[i];
  set.stats.generationSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return set;
}

}  // namespace vplab
