#include "renderer/offline/vpl_renderer.h"

#include "renderer/core/sampling.h"
#include "renderer/offline/direct_light.h"
#include "renderer/scene/brdf_params.h"
#include "renderer/vpl/vpl_contribution.h"
#include "renderer/vpl/vpl_generation.h"
#include "renderer/vpl/vsl_integral.h"

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
  std::vector<VslEnd> vslEnds;       ///< the VPL ends of the VSL exchanges (Method::Vsl)
  std::vector<uint8_t> vplLambert;   ///< whether f(x2) is pure Lambert (Method::Vsl)
  Method method;
  float clampBound;
  int vslSamples = 1;
  int maxDepth = 1;
};

/// Per-gather counters (the VPL part only).
struct GatherTally {
  double clampedLum = 0.0;
  double unclampedLum = 0.0;
  uint64_t shadowRays = 0;
  uint64_t evaluations = 0;
};

/// Unoccluded VSL contribution Phi T (see vpl_renderer.h for the definition of T and its estimator).
glm::vec3 vslContribution(const Context& ctx, const ShadingPoint& sp, std::size_t index, Rng& rng) {
  const Vpl& vpl = ctx.vpls[index];
  const float radius = ctx.radii[index];
  if (!(radius > 0.0f)) return vplUnoccludedContribution(sp, vpl, ctx.vplBrdfs[index], kInfinity);
  const VslEnd x1{sp.hit.position, sp.hit.shadingNormal, sp.hit.geometricNormal, sp.wo, sp.brdf};
  const VslEnd& x2 = ctx.vslEnds[index];
  const glm::vec3 d = x2.position - x1.position;
  // A cone entirely behind either surface carries nothing.
  if (glm::dot(x1.geometricNormal, d) < -radius || glm::dot(x2.geometricNormal, d) > radius) return glm::vec3(0.0f);
  // Both surfaces facing the same way (coplanar walls, a block's top and the floor): no direction leaves x1's front
  // side and reaches the VPL's front side.
  if (glm::dot(x1.geometricNormal, x2.geometricNormal) >= 1.0f - 1e-6f) return glm::vec3(0.0f);
  const bool lambert1 = isPureLambert(x1.brdf), lambert2 = ctx.vplLambert[index] != 0;
  // Step 1: a pure-Lambert pair whose cone no plane cuts has the closed form (vsl_integral.h): no samples.
  if (lambert1 && lambert2 && vslConeUnclipped(x1, x2, radius)) return vpl.flux * vslLambertTransfer(x1, x2, radius);
  // Step 2: one-sample MIS over the strategies that fit the pair (balance heuristic, Veach 1997): each of the S
  // samples picks the cone with probability pCone, else the BRDF of a glossy end (x1's f(x1) cos1, or the VPL's
  // f(x2) cos2 toward -w); its weight is g / (sum_k p_k pdf_k).
  const VslCone cone = vslCone(d, radius, x1.normal);
  const float pdfCone = 1.0f / cone.solidAngle;
  const float pB1 = lambert1 ? 0.0f : (lambert2 ? 0.5f : 0.25f);
  const float pB2 = lambert2 ? 0.0f : (lambert1 ? 0.5f : 0.25f);
  const float pCone = 1.0f - pB1 - pB2;
  const Frame frame(cone.axis);
  glm::vec3 sum(0.0f);
  for (int s = 0; s < ctx.vslSamples; ++s) {
    float pick = rng.next1D();
    glm::vec3 u(rng.next1D(), rng.next1D(), rng.next1D());
    // A BRDF sample brings its own f and pdf; the other end's are evaluated below.
    glm::vec3 w, f1(-1.0f), f2(-1.0f);
    float pdf1 = -1.0f, pdf2 = -1.0f;
    if (pick < pCone) {
      w = frame.toWorld(sampleUniformCone({u.y, u.z}, cone.cosThetaMax));
    } else if (pick < pCone + pB1) {
      BrdfSample bs = sampleBrdf(x1.brdf, x1.normal, x1.wo, u);
      if (!bs.valid()) continue;
      w = bs.wi, f1 = bs.f, pdf1 = bs.pdf;
    } else {
      BrdfSample bs = sampleBrdf(x2.brdf, x2.normal, x2.wo, u);
      if (!bs.valid()) continue;
      w = -bs.wi, f2 = bs.f, pdf2 = bs.pdf;
    }
    // Omega bounds the integral: directions outside the cone count zero. One-sided surfaces at both ends, as for
    // point VPLs.
    if (glm::dot(w, cone.axis) < cone.cosThetaMax) continue;
    if (glm::dot(x1.geometricNormal, w) <= 0.0f || glm::dot(x2.geometricNormal, w) >= 0.0f) continue;
    float cos1 = glm::dot(x1.normal, w), cos2 = -glm::dot(x2.normal, w);
    if (cos1 <= 0.0f || cos2 <= 0.0f) continue;
    if (f1.r < 0.0f) f1 = evaluateBrdfForVpl(x1.brdf, x1.normal, x1.wo, w);
    if (f2.r < 0.0f) f2 = evaluateBrdfForVpl(x2.brdf, x2.normal, x2.wo, -w);
    float pdf = pCone * pdfCone;
    if (pB1 > 0.0f) pdf += pB1 * (pdf1 >= 0.0f ? pdf1 : brdfPdf(x1.brdf, x1.normal, x1.wo, w));
    if (pB2 > 0.0f) pdf += pB2 * (pdf2 >= 0.0f ? pdf2 : brdfPdf(x2.brdf, x2.normal, x2.wo, -w));
    sum += f1 * f2 * (cos1 * cos2 / pdf);
  }
  // Step 3: the flux spread over the sphere's cross-section, Phi / (pi r^2).
  return vpl.flux * sum * (1.0f / (static_cast<float>(ctx.vslSamples) * kPi * radius * radius));
}

/// sum_i C_i(x1) V(x1, x2_i) with batched exact shadow rays (docs/theory.md §1, §4, §7).
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
      c = vslContribution(ctx, sp, i, rng);
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

/// Kollig & Keller 2004 compensation K(x1) of the residual transport T_r (docs/theory.md §5; see vpl_renderer.h).
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
  Context ctx{scene, embree, lights, vplSet.vpls, {}, {}, {}, {}, method, settings.clampBound};
  ctx.vplBrdfs.reserve(vplSet.vpls.size());
  for (const Vpl& v : vplSet.vpls) ctx.vplBrdfs.push_back(brdfParamsAt(scene, v.material, v.uv));
  if (method == Method::Vsl) {
    ctx.radii = vslRadii(vplSet.vpls, settings, scene.bounds.diagonal());
    ctx.clampBound = kInfinity;
    for (std::size_t i = 0; i < vplSet.vpls.size(); ++i) {
      const Vpl& v = vplSet.vpls[i];
      ctx.vslEnds.push_back({v.position, v.normal, v.geometricNormal, v.incoming, ctx.vplBrdfs[i]});
      ctx.vplLambert.push_back(isPureLambert(ctx.vplBrdfs[i]) ? 1 : 0);
    }
  }
  ctx.vslSamples = std::max(1, settings.vslSamples);
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
    if (wantDirect) radiance += lights.emittedRadiance(hit->triangle, hit->geometricNormal, hit->uv, sp.wo);
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
