#include "renderer/offline/vpl_renderer.h"

#include "renderer/core/sampling.h"
#include "renderer/offline/direct_light.h"
#include "renderer/scene/brdf_params.h"
#include "renderer/vpl/vpl_contribution.h"
#include "renderer/vpl/vpl_generation.h"

#include <array>
#include <cassert>
#include <cmath>
#include <optional>

namespace vplab {

namespace {

/// Shadow rays per occludedBatch call: a multiple of Embree's 8-wide packets, small enough to stay in L1.
constexpr std::size_t kShadowBatch = 64;

struct Context {
  const Scene& scene;
  const EmbreeScene& embree;
  const LightSampler& lights;
  const std::vector<Vpl>& vpls;
  std::vector<BrdfParams> vplBrdfs;  ///< f(x2) parameters, looked up once per render
  std::vector<float> radii;          ///< VSL radii (Method::Vsl)
  Method method;
  float clampBound;
  int coneSamples = 0;
  int brdfSamples = 0;
  int maxDepth = 1;
};

/// Per-gather counters (the VPL part only).
struct GatherTally {
  double clampedLum = 0.0;
  double unclampedLum = 0.0;
  uint64_t shadowRays = 0;
  uint64_t evaluations = 0;
};

/// f(x1; wo, w) f(x2; w_in, -w) cos1 cos2 for one direction w from x1 toward a VSL (MANYLIGHTS 7 integrand).
glm::vec3 vslIntegrand(const ShadingPoint& sp, const Vpl& vpl, const BrdfParams& vplBrdf, const glm::vec3& w) {
  // One-sided surfaces at both ends, as for point VPLs.
  if (glm::dot(sp.hit.geometricNormal, w) <= 0.0f || glm::dot(vpl.geometricNormal, w) >= 0.0f) return glm::vec3(0.0f);
  float cos1 = glm::dot(sp.hit.shadingNormal, w);
  float cos2 = -glm::dot(vpl.normal, w);
  if (cos1 <= 0.0f || cos2 <= 0.0f) return glm::vec3(0.0f);
  return evaluateBrdf(sp.brdf, sp.hit.shadingNormal, sp.wo, w) * evaluateBrdf(vplBrdf, vpl.normal, vpl.incoming, -w) *
         (cos1 * cos2);
}

/// Unoccluded VSL contribution Phi / (pi r^2) * integral over the cone (see vpl_renderer.h for the definition).
glm::vec3 vslContribution(const Context& ctx, const ShadingPoint& sp, const Vpl& vpl, const BrdfParams& vplBrdf,
                          float radius, Rng& rng) {
  if (!(radius > 0.0f)) return vplUnoccludedContribution(sp, vpl, vplBrdf, kInfinity);
  glm::vec3 d = vpl.position - sp.hit.position;
  float dist2 = glm::dot(d, d);
  float r2 = radius * radius;
  // Step 1: the cone subtended by the sphere; inside the sphere, every direction (cos theta_max = -1).
  float cosThetaMax = -1.0f, oneMinusCos = 2.0f;
  if (dist2 > r2) {
    float s2 = r2 / dist2;  // sin^2 theta_max
    float root = std::sqrt(1.0f - s2);
    cosThetaMax = root;
    oneMinusCos = s2 / (1.0f + root);  // 1 - cos without cancellation for tiny r
  }
  const float pdfCone = 1.0f / (2.0f * kPi * oneMinusCos);
  glm::vec3 axis = dist2 > 0.0f ? d / std::sqrt(dist2) : sp.hit.shadingNormal;
  Frame frame(axis);
  const float nCone = static_cast<float>(ctx.coneSamples), nBrdf = static_cast<float>(ctx.brdfSamples);
  glm::vec3 sum(0.0f);
  // Step 2: cone samples, balance-heuristic weighted against BRDF sampling (Veach 1997, multi-sample MIS).
  for (int s = 0; s < ctx.coneSamples; ++s) {
    glm::vec2 u = rng.next2D();
    glm::vec3 w = frame.toWorld(sampleUniformCone(u, cosThetaMax));
    glm::vec3 g = vslIntegrand(sp, vpl, vplBrdf, w);
    if (g.r <= 0.0f && g.g <= 0.0f && g.b <= 0.0f) continue;
    float pdfB = ctx.brdfSamples > 0 ? brdfPdf(sp.brdf, sp.hit.shadingNormal, sp.wo, w) : 0.0f;
    sum += g / (nCone * pdfCone + nBrdf * pdfB);
  }
  // Step 3: BRDF samples of f(x1); only directions inside the cone count (Omega bounds the integral).
  for (int s = 0; s < ctx.brdfSamples; ++s) {
    glm::vec3 u(rng.next1D(), rng.next1D(), rng.next1D());
    BrdfSample bs = sampleBrdf(sp.brdf, sp.hit.shadingNormal, sp.wo, u);
    if (!bs.valid() || glm::dot(bs.wi, axis) < cosThetaMax) continue;
    glm::vec3 g = vslIntegrand(sp, vpl, vplBrdf, bs.wi);
    if (g.r <= 0.0f && g.g <= 0.0f && g.b <= 0.0f) continue;
    sum += g / (nCone * pdfCone + nBrdf * bs.pdf);
  }
  // Step 4: the flux spread over the sphere's cross-section, Phi / (pi r^2).
  return vpl.flux * sum / (kPi * r2);
}

/// sum_i C_i(x1) V(x1, x2_i) with batched exact shadow rays (MANYLIGHTS 1, 4, 7).
/// trackUnclamped: also trace rays for VPLs whose clamped contribution is zero (b = 0), for the energy statistic.
glm::vec3 gatherVpls(const Context& ctx, const ShadingPoint& sp, Rng& rng, GatherTally& tally, bool trackUnclamped) {
  std::array<ShadowRay, kShadowBatch> rays;
  std::array<glm::vec3, kShadowBatch> clamped;
  std::array<float, kShadowBatch> unclampedLum;
  std::array<uint8_t, kShadowBatch> blocked;
  std::size_t n = 0;
  glm::vec3 sum(0.0f);
  auto flush = [&]() {
    ctx.embree.occludedBatch(rays.data(), blocked.data(), n);
    tally.shadowRays += n;
    for (std::size_t i = 0; i < n; ++i) {
      if (blocked[i]) continue;
      sum += clamped[i];
      tally.clampedLum += luminance(clamped[i]);
      tally.unclampedLum += unclampedLum[i];
    }
    n = 0;
  };
  const bool vsl = ctx.method == Method::Vsl;
  for (std::size_t i = 0; i < ctx.vpls.size(); ++i) {
    const Vpl& vpl = ctx.vpls[i];
    glm::vec3 c, u;
    if (vsl) {
      c = vslContribution(ctx, sp, vpl, ctx.vplBrdfs[i], ctx.radii[i], rng);
      u = c;
    } else {
      c = vplUnoccludedContribution(sp, vpl, ctx.vplBrdfs[i], ctx.clampBound, &u);
    }
    ++tally.evaluations;
    // Only VPLs that could contribute cost a shadow ray.
    bool useful = c.r > 0.0f || c.g > 0.0f || c.b > 0.0f;
    if (!useful && !(trackUnclamped && (u.r > 0.0f || u.g > 0.0f || u.b > 0.0f))) continue;
    rays[n] = ctx.embree.shadowRayBetween(sp.hit.position, sp.hit.geometricNormal, vpl.position, vpl.geometricNormal);
    clamped[n] = c;
    unclampedLum[n] = luminance(u);
    if (++n == kShadowBatch) flush();
  }
  if (n > 0) flush();
  return sum;
}

/// Kollig & Keller 2004 compensation K(x1) of the residual transport T_r (MANYLIGHTS 5; see vpl_renderer.h).
glm::vec3 compensation(const Context& ctx, const ShadingPoint& sp, Rng& rng, int depth, GatherTally& tally) {
  // Step 1: sample w from f(x1) cos and trace to x2.
  glm::vec3 u(rng.next1D(), rng.next1D(), rng.next1D());
  BrdfSample bs = sampleBrdf(sp.brdf, sp.hit.shadingNormal, sp.wo, u);
  if (!bs.valid() || !facesDirection(sp.hit, bs.wi)) return glm::vec3(0.0f);
  glm::vec3 origin = ctx.embree.offsetOrigin(sp.hit.position, sp.hit.geometricNormal, bs.wi);
  std::optional<SurfaceHit> next = ctx.embree.intersect(origin, bs.wi);
  if (!next || !facesDirection(*next, -bs.wi)) return glm::vec3(0.0f);

  // Step 2: only inside the bounded region (G > b) does the residual max(G - b, 0) = G (1 - b/G) act.
  float cos1 = glm::dot(sp.hit.shadingNormal, bs.wi);
  float cos2 = std::max(0.0f, -glm::dot(next->shadingNormal, bs.wi));
  glm::vec3 seg = next->position - sp.hit.position;
  float dist2 = glm::dot(seg, seg);
  if (!(cos1 > 0.0f) || !(dist2 > 0.0f)) return glm::vec3(0.0f);
  float g = cos1 * cos2 / dist2;
  if (!(g > ctx.clampBound)) return glm::vec3(0.0f);

  // Step 3: L(x2 -> x1) without Le(x2): direct light + bounded VPL estimate + the compensation at x2.
  ShadingPoint x2;
  x2.hit = *next;
  x2.wo = -bs.wi;
  x2.brdf = brdfParamsAt(ctx.scene, next->material, next->uv);
  glm::vec3 l = estimateDirectLight(ctx.embree, ctx.lights, x2.hit, x2.wo, x2.brdf, rng);
  GatherTally inner;
  l += gatherVpls(ctx, x2, rng, inner, false);
  tally.shadowRays += inner.shadowRays;
  tally.evaluations += inner.evaluations;
  if (depth + 1 < ctx.maxDepth) l += compensation(ctx, x2, rng, depth + 1, tally);

  // Step 4: f(x1) (1 - b/G) cos1 L / p: G dA = cos1 dw turns the area integral into the solid-angle one.
  return bs.f * l * ((1.0f - ctx.clampBound / g) * cos1 / bs.pdf);
}

}  // namespace

VplRenderResult renderVpl(const OfflineScene& offline, const VplSet& vplSet, Method method, const Settings& settings,
                          RenderControl* control, std::function<void(const Image& mean, int samplesSoFar)> onPass) {
  const Scene& scene = offline.scene();
  const EmbreeScene& embree = offline.embree();
  const LightSampler& lights = offline.lights();
  assert(method == Method::Vpl || method == Method::VplKK || method == Method::Vsl);
  Context ctx{scene, embree, lights, vplSet.vpls, {}, {}, method, settings.clampBound};
  ctx.vplBrdfs.reserve(vplSet.vpls.size());
  for (const Vpl& v : vplSet.vpls) ctx.vplBrdfs.push_back(brdfParamsAt(scene, v.material, v.uv));
  if (method == Method::Vsl) {
    ctx.radii = vslRadii(vplSet.vpls, settings, scene.bounds.diagonal());
    ctx.clampBound = kInfinity;
  }
  ctx.coneSamples = (std::max(1, settings.vslSamples) + 1) / 2;
  ctx.brdfSamples = std::max(1, settings.vslSamples) / 2;
  ctx.maxDepth = std::max(1, settings.maxDepth);

  const bool wantDirect = settings.components != Components::Indirect;
  const bool wantIndirect = settings.components != Components::Direct;
  const std::size_t pixels = static_cast<std::size_t>(std::max(0, settings.width)) * std::max(0, settings.height);
  // Per-pixel tallies: a pixel is only ever touched by one thread at a time, so no atomics and no thread ids.
  std::vector<GatherTally> tallies(pixels);

  ProgressiveOptions options = progressiveOptions(settings, 1, std::move(onPass));

  PixelEstimator estimator = [&](int x, int y, uint32_t, Rng& rng) -> glm::vec3 {
    // Step 1: primary ray through a jittered pixel position.
    glm::vec2 jitter = rng.next2D();
    glm::vec3 dir = cameraRayDirection(scene.camera, static_cast<float>(x) + jitter.x,
                                       static_cast<float>(y) + jitter.y, settings.width, settings.height);
    std::optional<SurfaceHit> hit = embree.intersect(scene.camera.position, dir);
    if (!hit) return glm::vec3(0.0f);
    ShadingPoint sp;
    sp.hit = *hit;
    sp.wo = -dir;
    glm::vec3 radiance(0.0f);
    // Step 2: emission seen directly, as the reference counts it (one-sided emitters).
    if (wantDirect) radiance += lights.emittedRadiance(hit->triangle, hit->geometricNormal, sp.wo);
    if (!facesDirection(*hit, sp.wo)) return radiance;
    sp.brdf = brdfParamsAt(scene, hit->material, hit->uv);
    // Step 3: direct light, the reference's estimator (next-event estimation + BRDF sampling, MIS).
    if (wantDirect) radiance += estimateDirectLight(embree, lights, sp.hit, sp.wo, sp.brdf, rng);
    if (!wantIndirect) return radiance;
    // Step 4: indirect light from the VPLs (bounded, or spherical), then Kollig-Keller's compensation.
    GatherTally& tally = tallies[static_cast<std::size_t>(y) * settings.width + x];
    GatherTally primary;
    radiance += gatherVpls(ctx, sp, rng, primary, true);
    tally.clampedLum += primary.clampedLum;
    tally.unclampedLum += primary.unclampedLum;
    tally.shadowRays += primary.shadowRays;
    tally.evaluations += primary.evaluations;
    if (method == Method::VplKK && std::isfinite(ctx.clampBound))
      radiance += compensation(ctx, sp, rng, 0, tally);
    return radiance;
  };

  VplRenderResult result;
  static_cast<ProgressiveResult&>(result) = renderProgressive(options, estimator, control);
  double clamped = 0.0, unclamped = 0.0;
  for (const GatherTally& t : tallies) {
    clamped += t.clampedLum;
    unclamped += t.unclampedLum;
    result.shadowRays += t.shadowRays;
    result.vplEvaluations += t.evaluations;
  }
  result.clampEnergyRemoved = unclamped > 0.0 ? (unclamped - clamped) / unclamped : 0.0;
  return result;
}

}  // namespace vplab
