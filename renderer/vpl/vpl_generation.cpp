#include "renderer/vpl/vpl_generation.h"

#include "renderer/core/sampling.h"
#include "renderer/offline/progressive.h"
#include "renderer/scene/brdf_params.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <optional>

namespace vplab {

namespace {

// Stream tags: each kind of decision gets its own random stream, so adding one never shifts another.
constexpr uint64_t kTagHaltonOffset = 0x48414c544f4eull;
constexpr uint64_t kTagPathTail = 0x5041544854ull;
constexpr uint64_t kTagPilot = 0x50494c4f54ull;
constexpr uint64_t kTagAccept = 0x414343455054ull;

/// Halton dimensions: light choice (1), point on the light (2), direction (2), first BRDF sample (3).
constexpr int kHaltonDims = 8;
constexpr std::array<uint32_t, kHaltonDims> kHaltonBases = {2, 3, 5, 7, 11, 13, 17, 19};
/// Light paths per parallel work item (VPLs are concatenated in path order, so the set is thread-count independent).
constexpr int64_t kPathsPerItem = 128;
/// Shadow rays per occlusion batch in the importance estimate.
constexpr std::size_t kImportanceBatch = 64;

float radicalInverse(uint32_t base, uint64_t index) {
  const double invBase = 1.0 / base;
  double factor = invBase, result = 0.0;
  while (index > 0) {
    result += factor * static_cast<double>(index % base);
    index /= base;
    factor *= invBase;
  }
  return std::min(static_cast<float>(result), kOneMinusEpsilon);
}

/// The random numbers of one light path: Halton (Cranley-Patterson rotated) for the first kHaltonDims decisions of
/// the main paths, then a PCG stream of the path. Pilot paths use PCG only, independent of the main paths.
class PathSampler {
 public:
  PathSampler(uint64_t pathIndex, const std::array<float, kHaltonDims>* offsets, uint64_t streamKey)
      : index_(pathIndex), offsets_(offsets), rng_(streamKey) {}

  float next() {
    if (offsets_ && dim_ < kHaltonDims) {
      float u = radicalInverse(kHaltonBases[dim_], index_) + (*offsets_)[dim_];
      ++dim_;
      if (u >= 1.0f) u -= 1.0f;
      return std::min(u, kOneMinusEpsilon);
    }
    ++dim_;
    return rng_.next1D();
  }

 private:
  uint64_t index_;
  const std::array<float, kHaltonDims>* offsets_;
  Rng rng_;
  int dim_ = 0;
};

/// One light path (MANYLIGHTS 2). VPL fluxes are the raw path throughput alpha (not yet divided by N_paths).
void traceLightPath(const Scene& scene, const EmbreeScene& embree, const LightSampler& lights, int maxBounces,
                    PathSampler& sampler, std::vector<Vpl>& out) {
  // Step 1: emission sample. The sampler draws the light by power, a point uniform on its area and a cosine
  // direction; weight = Le cos / (p_light pdf_A pdf_dir) = alpha_0 (before the 1/N_paths normalisation). A
  // directional light starts on a disk covering the scene, pdf_A = 1 / (pi R^2), weight E pi R^2 / p_light
  // (LightSampler::sampleEmission, docs/methods.md "Directional lights").
  float uLight = sampler.next();
  glm::vec2 uPoint(sampler.next(), sampler.next());
  glm::vec2 uDir(sampler.next(), sampler.next());
  EmissionSample e = lights.sampleEmission(uLight, uPoint, uDir);
  if (!e.valid) return;
  glm::vec3 alpha = e.weight;
  const float alpha0Max = std::max({alpha.r, alpha.g, alpha.b});
  if (!(alpha0Max > 0.0f)) return;
  glm::vec3 origin = glm::dot(e.normal, e.normal) > 0.0f ? embree.offsetOrigin(e.position, e.normal, e.direction)
                                                         : e.position;
  glm::vec3 dir = e.direction;

  for (int bounce = 1; bounce <= maxBounces; ++bounce) {
    // Step 2: find the next surface. The vertex on the light is not a VPL: direct light is computed exactly.
    std::optional<SurfaceHit> hit = embree.intersect(origin, dir);
    if (!hit) return;
    glm::vec3 wIn = -dir;
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
    if (bounce == maxBounces) return;

    // Step 4: continue by BRDF sampling, alpha *= f cos / pdf (the three numbers are drawn whatever happens).
    glm::vec3 u(sampler.next(), sampler.next(), sampler.next());
    BrdfParams params = brdfParamsAt(scene, hit->material, hit->uv);
    BrdfSample bs = sampleBrdf(params, hit->shadingNormal, wIn, u);
    if (!bs.valid() || glm::dot(hit->geometricNormal, bs.wi) <= 0.0f) return;
    float cosI = glm::dot(hit->shadingNormal, bs.wi);
    if (!(cosI > 0.0f)) return;
    alpha *= bs.f * (cosI / bs.pdf);

    // Step 5: Russian roulette on the throughput relative to alpha_0: survivors are scaled back up, so VPLs carry
    // roughly equal flux (Keller 1997) and dark paths end early.
    float uRr = sampler.next();
    float survive = std::min(1.0f, std::max({alpha.r, alpha.g, alpha.b}) / alpha0Max);
    if (!(survive > 0.0f) || uRr >= survive) return;
    alpha /= survive;

    origin = embree.offsetOrigin(hit->position, hit->geometricNormal, bs.wi);
    dir = bs.wi;
  }
}

/// Georgiev & Slusallek 2010, Phi_i: mean over the camera-visible points of the luminance a VPL sends there, with
/// exact visibility and the unbounded G (so the VPL set does not depend on the clamp bound).
double vplImportance(const Scene& scene, const EmbreeScene& embree, const std::vector<ShadingPoint>& points,
                     const Vpl& vpl) {
  if (points.empty()) return 0.0;
  BrdfParams vplBrdf = brdfParamsAt(scene, vpl.material, vpl.uv);
  std::array<ShadowRay, kImportanceBatch> rays;
  std::array<float, kImportanceBatch> values;
  std::array<uint8_t, kImportanceBatch> blocked;
  double sum = 0.0;
  std::size_t n = 0;
  auto flush = [&]() {
    embree.occludedBatch(rays.data(), blocked.data(), n);
    for (std::size_t i = 0; i < n; ++i)
      if (!blocked[i]) sum += values[i];
    n = 0;
  };
  for (const ShadingPoint& sp : points) {
    glm::vec3 c = vplUnoccludedContribution(sp, vpl, vplBrdf, kInfinity);
    float lum = luminance(c);
    if (!(lum > 0.0f) || !std::isfinite(lum)) continue;
    rays[n] = embree.shadowRayBetween(sp.hit.position, sp.hit.geometricNormal, vpl.position, vpl.geometricNormal);
    values[n] = lum;
    ++n;
    if (n == kImportanceBatch) flush();
  }
  if (n > 0) flush();
  return sum / static_cast<double>(points.size());
}

}  // namespace

std::vector<ShadingPoint> rejectionSamplePoints(const OfflineScene& offline, const Settings& settings) {
  const Scene& scene = offline.scene();
  const EmbreeScene& embree = offline.embree();
  std::vector<ShadingPoint> points;
  const int m = std::max(1, settings.rejectionSamplePoints);
  const float aspect = static_cast<float>(settings.width) / static_cast<float>(std::max(1, settings.height));
  // A grid of about m cells with the image's aspect ratio; one primary ray through each cell centre.
  int gx = std::max(1, static_cast<int>(std::lround(std::sqrt(static_cast<double>(m) * aspect))));
  int gy = std::max(1, static_cast<int>(std::lround(static_cast<double>(m) / gx)));
  points.reserve(static_cast<std::size_t>(gx) * gy);
  for (int j = 0; j < gy; ++j)
    for (int i = 0; i < gx; ++i) {
      float px = (static_cast<float>(i) + 0.5f) / gx * static_cast<float>(settings.width);
      float py = (static_cast<float>(j) + 0.5f) / gy * static_cast<float>(settings.height);
      glm::vec3 dir = cameraRayDirection(scene.camera, px, py, settings.width, settings.height);
      std::optional<SurfaceHit> hit = embree.intersect(scene.camera.position, dir);
      if (!hit || glm::dot(hit->geometricNormal, -dir) <= 0.0f) continue;
      ShadingPoint sp;
      sp.hit = *hit;
      sp.wo = -dir;
      sp.brdf = brdfParamsAt(scene, hit->material, hit->uv);
      points.push_back(sp);
    }
  return points;
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
  const EmbreeScene& embree = offline.embree();
  const LightSampler& lights = offline.lights();
  const auto start = std::chrono::steady_clock::now();
  VplSet set;
  auto finish = [&]() {
    set.stats.accepted = set.vpls.size();
    set.stats.acceptanceRate =
        set.stats.candidates > 0 ? static_cast<double>(set.stats.accepted) / set.stats.candidates : 1.0;
    std::vector<float> radii = vslRadii(set.vpls, settings, scene.bounds.diagonal());
    for (std::size_t i = 0; i < set.vpls.size(); ++i) set.vpls[i].radius = radii[i];
    set.stats.generationSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return set;
  };
  if (settings.vplCount <= 0 || lights.empty() || scene.triangles.empty()) return finish();
  const int maxBounces = std::max(1, settings.vplMaxBounces);
  const bool reject = settings.rejection;

  // Pilot (own random stream, independent of the main paths): mean VPLs per light path and, with rejection, the
  // average VPL contribution Phi_v and the mean acceptance probability (Georgiev & Slusallek 2010, step 1).
  std::vector<Vpl> pilot;
  int64_t pilotPaths = 0;
  const std::size_t wantedPilotVpls = reject ? static_cast<std::size_t>(std::max(1, settings.rejectionPilotVpls)) : 0;
  const int64_t maxPilotPaths = 64 * std::max<int64_t>(kVplPilotPaths, static_cast<int64_t>(wantedPilotVpls));
  while (pilotPaths < maxPilotPaths && (pilotPaths < kVplPilotPaths || pilot.size() < wantedPilotVpls)) {
    PathSampler sampler(static_cast<uint64_t>(pilotPaths), nullptr,
                        hashKey(settings.seed, static_cast<uint64_t>(pilotPaths), kTagPilot));
    traceLightPath(scene, embree, lights, maxBounces, sampler, pilot);
    ++pilotPaths;
  }
  const double vplsPerPath = static_cast<double>(pilot.size()) / static_cast<double>(pilotPaths);

  std::vector<ShadingPoint> points;
  double phiV = 0.0;
  double acceptedPerPath = vplsPerPath;
  if (reject && !pilot.empty()) {
    points = rejectionSamplePoints(offline, settings);
    std::size_t evaluated = std::min(pilot.size(), wantedPilotVpls);
    std::vector<double> phi(evaluated);
    parallelFor(static_cast<int64_t>(evaluated), settings.threads, [&](int64_t i, int) {
      phi[static_cast<std::size_t>(i)] = vplImportance(scene, embree, points, pilot[static_cast<std::size_t>(i)]);
    });
    for (double p : phi) phiV += p;
    phiV /= static_cast<double>(evaluated);
    // Expected accepted VPLs per path = VPLs per path x mean p_i over the pilot VPLs.
    if (phiV > 0.0) {
      double meanAccept = 0.0;
      for (double p : phi) meanAccept += std::min(p / phiV + settings.rejectionEpsilon, 1.0);
      acceptedPerPath = vplsPerPath * meanAccept / static_cast<double>(evaluated);
    }
  }

  // Plan N_paths before tracing so that it does not depend on the paths it normalises. The candidate cap limits
  // the expected candidates to rejectionMaxCandidateFactor x vplCount.
  const double maxCandidates =
      static_cast<double>(settings.rejectionMaxCandidateFactor) * static_cast<double>(settings.vplCount);
  double plannedPaths = acceptedPerPath > 0.0 ? std::ceil(settings.vplCount / acceptedPerPath)
                                               : static_cast<double>(settings.vplCount);
  if (vplsPerPath > 0.0 && plannedPaths * vplsPerPath > maxCandidates) {
    plannedPaths = std::max(1.0, std::floor(maxCandidates / vplsPerPath));
    set.stats.candidateCapReached = true;
  }
  const int64_t paths = static_cast<int64_t>(std::clamp(plannedPaths, 1.0, 1.0e9));

  // Main paths: Halton rotated by the seed for the first decisions (temporal coherence, stratification).
  std::array<float, kHaltonDims> offsets;
  for (int d = 0; d < kHaltonDims; ++d)
    offsets[d] = static_cast<float>(hashKey(settings.seed, static_cast<uint64_t>(d), kTagHaltonOffset) >> 40) *
                 0x1p-24f;
  const bool useRejection = reject && phiV > 0.0;
  const int64_t items = (paths + kPathsPerItem - 1) / kPathsPerItem;
  struct Chunk {
    std::vector<Vpl> accepted, rejected;
    uint64_t candidates = 0;
  };
  std::vector<Chunk> chunks(static_cast<std::size_t>(items));
  parallelFor(
      items, settings.threads,
      [&](int64_t item, int) {
        Chunk& chunk = chunks[static_cast<std::size_t>(item)];
        std::vector<Vpl> candidates;
        const int64_t end = std::min(paths, (item + 1) * kPathsPerItem);
        for (int64_t j = item * kPathsPerItem; j < end; ++j) {
          candidates.clear();
          PathSampler sampler(static_cast<uint64_t>(j), &offsets,
                              hashKey(settings.seed, static_cast<uint64_t>(j), kTagPathTail));
          traceLightPath(scene, embree, lights, maxBounces, sampler, candidates);
          chunk.candidates += candidates.size();
          if (!useRejection) {
            chunk.accepted.insert(chunk.accepted.end(), candidates.begin(), candidates.end());
            continue;
          }
          // Rejection (Georgiev & Slusallek 2010, step 2): accept with p_i = min(Phi_i / Phi_v + epsilon, 1) and
          // divide the flux by p_i (Russian roulette on the expected contribution to the image).
          Rng acceptRng(hashKey(settings.seed, static_cast<uint64_t>(j), kTagAccept));
          for (Vpl& c : candidates) {
            float u = acceptRng.next1D();
            double p = std::min(vplImportance(scene, embree, points, c) / phiV + settings.rejectionEpsilon, 1.0);
            if (p > 0.0 && u < p) {
              c.flux /= static_cast<float>(p);
              chunk.accepted.push_back(c);
            } else {
              chunk.rejected.push_back(c);
            }
          }
        }
      },
      control);

  // Concatenate in path order and normalise by N_paths: every planned path counts, whether its candidates were
  // accepted, rejected or it never hit anything.
  const float invPaths = 1.0f / static_cast<float>(paths);
  for (Chunk& c : chunks) {
    set.stats.candidates += c.candidates;
    for (Vpl& v : c.accepted) {
      v.flux *= invPaths;
      set.vpls.push_back(v);
    }
    for (Vpl& v : c.rejected) {
      v.flux *= invPaths;
      set.rejected.push_back(v);
    }
  }
  set.stats.pathsTraced = static_cast<uint64_t>(paths);
  return finish();
}

}  // namespace vplab
