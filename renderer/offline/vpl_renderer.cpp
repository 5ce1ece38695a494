#include "renderer/offline/vpl_renderer.h"

#include <array>
#include <cassert>
#include <cmath>
#include <optional>

#include "renderer/core/sampling.h"
#include "renderer/offline/camera_sample.h"
#include "renderer/offline/direct_light.h"
#include "renderer/offline/medium_direct.h"
#include "renderer/scene/brdf_params.h"
#include "renderer/vpl/vpl_contribution.h"
#include "renderer/vpl/vpl_generation.h"
#include "renderer/vpl/vsl_integral.h"

namespace vplab {

/// What the VPL estimators read: the scene, the VPLs and the per-render tables derived from them.
struct VplContext {
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
  bool media = false;            ///< the scene has media: every transfer carries their transmittance
  std::vector<float> vplPhaseG;  ///< Henyey-Greenstein g of each medium VPL's medium (media scenes)
  float sceneDiagonal = 1.0f;
};

namespace {

using Context = VplContext;

/// Shadow rays per occludedBatch call: a multiple of Embree's 8-wide packets, small enough to stay in L1.
constexpr std::size_t kShadowBatch = 64;


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

/// sum_i C_i(x) V(x, x2_i) with batched exact shadow rays (docs/theory.md §1, §4, §7), at a surface point or (in a
/// scene with media) a medium point, every transfer then attenuated by the media's transmittance (§17).
/// trackUnclamped: also trace rays for VPLs whose clamped contribution is zero (b = 0), for the energy statistic.
glm::vec3 gatherVpls(const Context& ctx, const Interaction& x, Rng& rng, GatherTally& tally, bool trackUnclamped) {
  std::array<ShadowRay, kShadowBatch> rays;
  std::array<glm::vec3, kShadowBatch> clamped;
  std::array<float, kShadowBatch> unclampedLum;
  std::array<glm::vec3, kShadowBatch> unclamped;  ///< the unclamped colour, for the transmittance (media scenes)
  std::array<uint8_t, kShadowBatch> blocked;
  std::size_t n = 0;
  glm::vec3 sum(0.0f);
  auto flush = [&]() {
    ctx.embree.occludedBatch(rays.data(), blocked.data(), n);
    tally.shadowRays += n;
    for (std::size_t i = 0; i < n; ++i) {
      if (blocked[i]) continue;
      glm::vec3 c = clamped[i];
      float u = unclampedLum[i];
      if (ctx.media) {
        // The luminance of the attenuated colour, not the product of luminances (chromatic media).
        const glm::vec3 tr = ctx.embree.transmittance(rays[i].origin, rays[i].direction, rays[i].tMax);
        c *= tr;
        u = luminance(unclamped[i] * tr);
      }
      sum += c;
      tally.clampedLum += luminance(c);
      tally.unclampedLum += u;
    }
    n = 0;
  };
  const bool vsl = ctx.method == Method::Vsl;
  const ShadingPoint sp{x.hit, x.wo, x.brdf};
  for (std::size_t i = 0; i < ctx.vpls.size(); ++i) {
    const Vpl& vpl = ctx.vpls[i];
    glm::vec3 c, u;
    if (!ctx.media) {
      if (vsl) {
        c = vslContribution(ctx, sp, i, rng);
        u = c;
      } else {
        c = vplUnoccludedContribution(sp, vpl, ctx.vplBrdfs[i], ctx.clampBound, &u);
      }
    } else if (vsl && !x.inMedium && !vpl.inMedium) {
      c = vslContribution(ctx, sp, i, rng);
      u = c;
    } else {
      // Medium ends are point lights in every method (a VSL spreads a VPL over surfaces only).
      c = vplContributionAt(x, vpl, ctx.vplBrdfs[i], ctx.vplPhaseG[i], ctx.clampBound, &u);
    }
    ++tally.evaluations;
    // Only VPLs that could contribute cost a shadow ray.
    bool useful = c.r > 0.0f || c.g > 0.0f || c.b > 0.0f;
    if (!useful && !(trackUnclamped && (u.r > 0.0f || u.g > 0.0f || u.b > 0.0f))) continue;
    rays[n] = ctx.embree.shadowRayBetween(x.position, x.offsetNormal(), vpl.position,
                                          vpl.inMedium ? glm::vec3(0.0f) : vpl.geometricNormal);
    clamped[n] = c;
    unclampedLum[n] = luminance(u);
    unclamped[n] = u;
    if (++n == kShadowBatch) flush();
  }
  if (n > 0) flush();
  return sum;
}

/// Kollig & Keller 2004 compensation K(x1) of the residual transport T_r (docs/theory.md §5; see vpl_renderer.h),
/// and in media Raab et al. 2008 (§18): the direction from the BRDF or the phase function, the next vertex by a free
/// flight (a surface or a medium point), G with whichever cosines exist.
glm::vec3 compensation(const Context& ctx, const Interaction& x, Rng& rng, int depth, GatherTally& tally,
                       IncidentSample* incident = nullptr) {
  // Step 1: sample w from f(x1) cos (or f_p) and trace to x2.
  const Interaction::Sample bs = x.sample(rng);
  if (!bs.valid()) return glm::vec3(0.0f);
  glm::vec3 origin = x.rayOrigin(ctx.embree, bs.wi);
  Segment next = ctx.embree.traceSegment(origin, bs.wi, kInfinity, [&rng]() { return rng.next2D(); });
  if (next.end == Segment::End::Escape) return glm::vec3(0.0f);
  Interaction x2 = Interaction::atSegmentEnd(ctx.scene, next, -bs.wi);
  if (!x2.scatters()) return glm::vec3(0.0f);

  // Step 2: only inside the bounded region (G > b) does the residual max(G - b, 0) = G (1 - b/G) act.
  float cos1 = x.inMedium ? 1.0f : glm::dot(x.hit.shadingNormal, bs.wi);
  float cos2 = x2.inMedium ? 1.0f : std::max(0.0f, -glm::dot(x2.hit.shadingNormal, bs.wi));
  glm::vec3 seg = x2.position - x.position;
  float dist2 = glm::dot(seg, seg);
  if (!(cos1 > 0.0f) || !(dist2 > 0.0f)) return glm::vec3(0.0f);
  float g = cos1 * cos2 / dist2;
  if (!(g > ctx.clampBound)) return glm::vec3(0.0f);

  // Step 3: L(x2 -> x1) without Le(x2): direct light + bounded VPL estimate + the compensation at x2.
  glm::vec3 l = estimateDirectLight(ctx.embree, ctx.lights, x2, rng);
  GatherTally inner;
  l += gatherVpls(ctx, x2, rng, inner, false);
  tally.shadowRays += inner.shadowRays;
  tally.evaluations += inner.evaluations;
  if (depth + 1 < ctx.maxDepth) l += compensation(ctx, x2, rng, depth + 1, tally);

  // Step 4: f(x1) (1 - b/G) cos1 L / p: G dA = cos1 dw turns the area integral into the solid-angle one (f_p / p = 1
  // in a medium); through media the free flight's weight (T sigma_s / pdf or T / P) carries the distance integral.
  glm::vec3 result =
      x.inMedium ? l * (1.0f - ctx.clampBound / g) : bs.f * l * ((1.0f - ctx.clampBound / g) * cos1 / bs.pdf);
  if (incident && !x.inMedium) *incident = {bs.wi, l * ((1.0f - ctx.clampBound / g) * cos1 / bs.pdf)};
  return next.crossedMedium ? result * next.weight : result;
}

/// Approximate bias compensation in media (Engelhardt et al. 2012, docs/theory.md §18; see vpl_renderer.h): one
/// residual bounce. At a medium point x the residual acts only inside the ball |x - y| < 1/sqrt(b) (G = 1/d^2 there),
/// so y is drawn along a phase-sampled direction by a free flight in x's medium taken as homogeneous and unbounded
/// over that ball: no ray is traced (no local visibility, surfaces inside the ball ignored) and the recursion is cut.
/// A surface point gets one bounce of Kollig-Keller (exact, as screen-space compensation approximates it in GL).
glm::vec3 approximateCompensation(const Context& ctx, const Interaction& x, Rng& rng, GatherTally& tally) {
  if (!x.inMedium) return compensation(ctx, x, rng, ctx.maxDepth - 1, tally);
  // Step 1: a direction from the phase function and a channel for the distance (spectral MIS).
  glm::vec2 uDir = rng.next2D();
  glm::vec2 uDist = rng.next2D();
  const PhaseSample ps = samplePhaseHG(x.wo, x.g, uDir);
  // In a density grid the medium is taken as homogeneous with the coefficients at x (locally homogeneous at the
  // receiver, as Engelhardt et al. 2012 do for heterogeneous media).
  const Medium& medium = ctx.scene.media[x.medium];
  const glm::vec3 sigmaT = medium.sigmaTAt(x.position);
  const glm::vec3 sigmaS = medium.sigmaSAt(x.position);
  const float radius = 1.0f / std::sqrt(ctx.clampBound);
  // Step 2: t in [0, radius) with density proportional to sigma_t,c exp(-sigma_t,c t), truncated to the ball, for a
  // channel c picked uniformly; the pdf is the mean of the three channels' truncated densities.
  const int channel = std::min(2, static_cast<int>(uDist.x * 3.0f));
  auto truncatedMass = [&](int c) { return sigmaT[c] > 0.0f ? -std::expm1(-sigmaT[c] * radius) : 0.0f; };
  float t;
  if (sigmaT[channel] > 0.0f)
    t = -std::log1p(-uDist.y * truncatedMass(channel)) / sigmaT[channel];
  else
    t = uDist.y * radius;
  t = std::min(t, radius);
  if (!(t > 0.0f)) return glm::vec3(0.0f);
  float pdf = 0.0f;
  for (int c = 0; c < 3; ++c)
    pdf += sigmaT[c] > 0.0f ? sigmaT[c] * std::exp(-sigmaT[c] * t) / truncatedMass(c) : 1.0f / radius;
  pdf /= 3.0f;
  const float g = 1.0f / (t * t);
  if (!(g > ctx.clampBound) || !(pdf > 0.0f)) return glm::vec3(0.0f);
  // Step 3: the bounded estimate at y (direct light + VPL gather with visibility), no further compensation.
  const Interaction y = Interaction::inMediumAt(ctx.scene, x.position + ps.wi * t, x.medium, -ps.wi);
  glm::vec3 l = estimateDirectLight(ctx.embree, ctx.lights, y, rng);
  GatherTally inner;
  l += gatherVpls(ctx, y, rng, inner, false);
  tally.shadowRays += inner.shadowRays;
  tally.evaluations += inner.evaluations;
  // Step 4: f_p / pdf = 1; T(t) sigma_s / pdf(t) for the distance, (1 - b/G) for the residual.
  return l * sigmaS * glm::exp(-sigmaT * t) * ((1.0f - ctx.clampBound / g) / pdf);
}

/// The residual compensation the method asks for at x (zero for plain Vpl and Vsl or without a bound).
glm::vec3 compensationFor(const Context& ctx, const Interaction& x, Rng& rng, GatherTally& tally) {
  if (!std::isfinite(ctx.clampBound)) return glm::vec3(0.0f);
  if (ctx.method == Method::VplKK) return compensation(ctx, x, rng, 0, tally);
  if (ctx.method == Method::VplAbc) return approximateCompensation(ctx, x, rng, tally);
  return glm::vec3(0.0f);
}

/// The medium part of one camera sample (docs/theory.md §16-§18): integral over the media intervals of
/// T(0, t) sigma_s L_s(x(t)). Direct light (single scattering) and the compensation at one forced-flight distance, the
/// direct light also at an equiangular distance toward the light (MIS, medium_direct.h);
/// each VPL's in-scattering at a distance of its own, drawn equiangularly around it (Kulla & Fajardo 2012), which
/// cancels its 1/d^2 along the ray.
glm::vec3 mediumAlongRay(const Context& ctx, const glm::vec3& origin, const glm::vec3& dir,
                         const std::vector<MediumInterval>& intervals, float end, bool wantDirect, bool wantIndirect,
                         Rng& rng, GatherTally& tally) {
  // Step 1: one distance by forced free flight for the direct light and the residual compensation; the direct light
  // also by equiangular sampling toward the lights, MIS-weighted (docs/theory.md §24).
  glm::vec3 radiance = forcedFlightAlongRay(
      ctx.embree, ctx.lights, origin, dir, intervals, end, wantDirect, rng,
      [&](const Interaction& x) { return wantIndirect ? compensationFor(ctx, x, rng, tally) : glm::vec3(0.0f); });
  if (!wantIndirect || ctx.vpls.empty()) return radiance;

  // Step 2: every VPL's in-scattering along the ray, equiangular over the span of the media intervals. A span that
  // reaches infinity (a medium filling all space) is cut where the least attenuated channel's transmittance is 1e-6,
  // or at 1000 scene diagonals for a channel that does not attenuate (the VPLs' 1/d^2 has faded long before).
  const float a = intervals.front().t0;
  const float b = mediaSpanEnd(ctx.scene.media, intervals, end, ctx.sceneDiagonal);
  if (!(b > a)) return radiance;
  std::array<ShadowRay, kShadowBatch> rays;
  std::array<glm::vec3, kShadowBatch> clamped;
  std::array<glm::vec3, kShadowBatch> unclampedColour;
  std::array<uint8_t, kShadowBatch> blocked;
  std::size_t n = 0;
  auto flush = [&]() {
    ctx.embree.occludedBatch(rays.data(), blocked.data(), n);
    tally.shadowRays += n;
    for (std::size_t i = 0; i < n; ++i) {
      if (blocked[i]) continue;
      const glm::vec3 tr = ctx.embree.transmittance(rays[i].origin, rays[i].direction, rays[i].tMax);
      const glm::vec3 c = clamped[i] * tr;
      radiance += c;
      tally.clampedLum += luminance(c);
      tally.unclampedLum += luminance(unclampedColour[i] * tr);
    }
    n = 0;
  };
  const float minH = 1e-6f * ctx.sceneDiagonal;
  for (std::size_t i = 0; i < ctx.vpls.size(); ++i) {
    const Vpl& vpl = ctx.vpls[i];
    const float uT = rng.next1D();
    ++tally.evaluations;
    // A distance of its own, equiangular around the VPL; the medium there (between boxes there is none).
    float tv = 0.0f, pdf = 0.0f;
    const MediumInterval* in = sampleEquiangular(intervals, origin, dir, a, b, vpl.position, uT, minH, tv, pdf);
    if (!in) continue;
    const Interaction x = Interaction::inMediumAt(ctx.scene, origin + dir * tv, in->medium, -dir);
    glm::vec3 uc;
    glm::vec3 c = vplContributionAt(x, vpl, ctx.vplBrdfs[i], ctx.vplPhaseG[i], ctx.clampBound, &uc);
    if (!(c.r > 0.0f || c.g > 0.0f || c.b > 0.0f) && !(uc.r > 0.0f || uc.g > 0.0f || uc.b > 0.0f)) continue;
    const glm::vec3 w = ctx.scene.media[in->medium].sigmaSAt(x.position) *
                        transmittanceAlong(ctx.scene.media, intervals, origin, dir, tv) / pdf;
    rays[n] = ctx.embree.shadowRayBetween(x.position, glm::vec3(0.0f), vpl.position,
                                          vpl.inMedium ? glm::vec3(0.0f) : vpl.geometricNormal);
    clamped[n] = c * w;
    unclampedColour[n] = uc * w;
    if (++n == kShadowBatch) flush();
  }
  if (n > 0) flush();
  return radiance;
}

/// The tables every estimator reads, built once per render.
Context makeContext(const OfflineScene& offline, const VplSet& vplSet, Method method, const Settings& settings) {
  const Scene& scene = offline.scene();
  Context ctx{scene, offline.embree(), offline.lights(), vplSet.vpls, {}, {}, {}, {}, method, settings.clampBound};
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
  ctx.media = scene.hasMedia();
  ctx.sceneDiagonal = std::max(scene.bounds.diagonal(), 1e-6f);
  ctx.vplPhaseG.reserve(vplSet.vpls.size());
  for (const Vpl& v : vplSet.vpls) ctx.vplPhaseG.push_back(v.inMedium ? scene.media[v.medium].g : 0.0f);

  return ctx;
}

}  // namespace

VplTransport::VplTransport(const OfflineScene& offline, const VplSet& vpls, Method method, const Settings& settings)
    : ctx_(std::make_unique<VplContext>(makeContext(offline, vpls, method, settings))) {}

VplTransport::~VplTransport() = default;

glm::vec3 VplTransport::gather(const Interaction& x, Rng& rng, GatherTally& tally, bool trackUnclamped) const {
  return gatherVpls(*ctx_, x, rng, tally, trackUnclamped);
}

glm::vec3 VplTransport::compensation(const Interaction& x, Rng& rng, int depth, GatherTally& tally,
                                     IncidentSample* incident) const {
  return vplab::compensation(*ctx_, x, rng, depth, tally, incident);
}

glm::vec3 VplTransport::methodCompensation(const Interaction& x, Rng& rng, GatherTally& tally) const {
  return compensationFor(*ctx_, x, rng, tally);
}

const std::vector<Vpl>& VplTransport::vpls() const { return ctx_->vpls; }
const std::vector<BrdfParams>& VplTransport::vplBrdfs() const { return ctx_->vplBrdfs; }
float VplTransport::clampBound() const { return ctx_->clampBound; }
int VplTransport::maxDepth() const { return ctx_->maxDepth; }

VplRenderResult renderVpl(const OfflineScene& offline, const VplSet& vplSet, Method method, const Settings& settings,
                          RenderControl* control, std::function<void(const Image& mean, int samplesSoFar)> onPass) {
  const Scene& scene = offline.scene();
  const EmbreeScene& embree = offline.embree();
  const LightSampler& lights = offline.lights();
  assert(method == Method::Vpl || method == Method::VplKK || method == Method::Vsl || method == Method::VplAbc);
  const Context ctx = makeContext(offline, vplSet, method, settings);
  const bool wantDirect = settings.components != Components::Indirect;
  const bool wantIndirect = settings.components != Components::Direct;
  const std::size_t pixels = static_cast<std::size_t>(std::max(0, settings.width)) * std::max(0, settings.height);
  // Per-pixel tallies: a pixel is only ever touched by one thread at a time, so no atomics and no thread ids.
  std::vector<GatherTally> tallies(pixels);

  ProgressiveOptions options = progressiveOptions(settings, 1, std::move(onPass));

  PixelEstimator estimator = [&](int x, int y, uint32_t, Rng& rng) -> glm::vec3 {
    GatherTally& tally = tallies[static_cast<std::size_t>(y) * settings.width + x];
    const glm::vec3& camera = scene.camera.position;
    return manyLightCameraSample(
        embree, lights, settings, x, y, rng,
        [&](const glm::vec3& dir, const std::vector<MediumInterval>& intervals, float end) {
          return mediumAlongRay(ctx, camera, dir, intervals, end, wantDirect, wantIndirect, rng, tally);
        },
        [&](const Interaction& sp) {
          // Indirect light from the VPLs (bounded, or spherical), then the residual's compensation.
          GatherTally primary;
          glm::vec3 l = gatherVpls(ctx, sp, rng, primary, true);
          tally.clampedLum += primary.clampedLum;
          tally.unclampedLum += primary.unclampedLum;
          tally.shadowRays += primary.shadowRays;
          tally.evaluations += primary.evaluations;
          return l + compensationFor(ctx, sp, rng, tally);
        });
  };

  VplRenderResult result;
  static_cast<ProgressiveResult&>(result) = renderProgressive(options, estimator, control);
  addTallies(tallies, result);
  return result;
}

void addTallies(const std::vector<GatherTally>& tallies, VplRenderResult& result) {
  GatherTally total;
  for (const GatherTally& t : tallies) total.add(t);
  result.shadowRays += total.shadowRays;
  result.vplEvaluations += total.evaluations;
  result.clampEnergyRemoved =
      total.unclampedLum > 0.0 ? (total.unclampedLum - total.clampedLum) / total.unclampedLum : 0.0;
}

}  // namespace vplab
