#include "renderer/offline/vrl_renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "renderer/core/sampling.h"
#include "renderer/offline/camera_sample.h"
#include "renderer/offline/direct_light.h"
#include "renderer/offline/interaction.h"
#include "renderer/offline/medium_direct.h"
#include "renderer/scene/brdf_params.h"
#include "renderer/scene/medium.h"
#include "renderer/vpl/vpl_contribution.h"
#include "renderer/vpl/vpl_generation.h"

namespace vplab {

namespace {

/// Shadow rays per occludedBatch call (a multiple of Embree's 8-wide packets).
constexpr std::size_t kShadowBatch = 64;
/// Below this sin(theta) the camera line and a VRL count as parallel: v is then drawn uniformly.
constexpr float kParallelSin = 1e-4f;

struct Context {
  const Scene& scene;
  const EmbreeScene& embree;
  const LightSampler& lights;
  const std::vector<Vpl>& vpls;
  const std::vector<Vrl>& vrls;
  std::vector<BrdfParams> vplBrdfs;
  std::vector<uint32_t> surfaceVpls;  ///< indices of the surface VPLs (medium VPLs are replaced by the VRLs)
  /// T(start, start + t0 e) of each VRL: inside its one homogeneous medium T(start, v) = that exp(-sigma_t (v - t0)).
  std::vector<glm::vec3> vrlEntry;
  bool media = false;
  int vrlSamples = 1;
  float beamRadius = 0.0f;  ///< 0: VRLs; > 0: beams of this radius (Method::Vbl)
  float sceneDiagonal = 1.0f;
};

struct Tally {
  uint64_t shadowRays = 0;
  uint64_t evaluations = 0;
};

/// A batch of shadow rays whose contributions count (times the media's transmittance along the ray) when unblocked.
struct ShadowBatch {
  const EmbreeScene& embree;
  bool withTransmittance;
  Tally& tally;
  std::array<ShadowRay, kShadowBatch> rays;
  std::array<glm::vec3, kShadowBatch> values;
  std::array<uint8_t, kShadowBatch> blocked;
  std::size_t n = 0;
  glm::vec3 sum{0.0f};

  void add(const ShadowRay& ray, const glm::vec3& value) {
    rays[n] = ray;
    values[n] = value;
    if (++n == kShadowBatch) flush();
  }
  void flush() {
    if (n == 0) return;
    embree.occludedBatch(rays.data(), blocked.data(), n);
    tally.shadowRays += n;
    for (std::size_t i = 0; i < n; ++i) {
      if (blocked[i]) continue;
      glm::vec3 c = values[i];
      if (withTransmittance) c *= embree.transmittance(rays[i].origin, rays[i].direction, rays[i].tMax);
      sum += c;
    }
    n = 0;
  }
};

bool positive(const glm::vec3& c) {
  return c.r > 0.0f || c.g > 0.0f || c.b > 0.0f;
}

/// A shadow ray between two medium points (no offsets).
ShadowRay mediumRay(const glm::vec3& from, const glm::vec3& to) {
  ShadowRay r;
  const glm::vec3 d = to - from;
  r.tMax = glm::length(d);
  r.origin = from;
  r.direction = r.tMax > 0.0f ? d / r.tMax : glm::vec3(0.0f, 0.0f, 1.0f);
  return r;
}

/// A sampled point of a VRL (or of a beam around it): where it is, its distance v along the VRL and the pdf of v,
/// and the transmittance T(start', x_v') along the (offset) line.
struct VrlPoint {
  glm::vec3 position{0.0f};
  glm::vec3 weight{0.0f};  ///< Phi sigma_s T(start, v) / p(v)
};

/// A point offset uniformly in the disc of radius r perpendicular to e (zero offset for r = 0).
glm::vec3 discOffset(const glm::vec3& e, float r, glm::vec2 u) {
  if (!(r > 0.0f)) return glm::vec3(0.0f);
  const Frame frame(e);
  const float rho = r * std::sqrt(u.x);
  const float phi = 2.0f * kPi * u.y;
  return frame.toWorld(glm::vec3(rho * std::cos(phi), rho * std::sin(phi), 0.0f));
}

/// Finishes a VRL point at parameter v with pdf p(v): the disc offset of a beam, the transmittance along it.
bool finishVrlPoint(const Context& ctx, const Vrl& vrl, float v, float pdf, Rng& rng, VrlPoint& out) {
  const glm::vec2 uDisc = rng.next2D();
  if (!(pdf > 0.0f) || !std::isfinite(v) || !std::isfinite(pdf)) return false;
  glm::vec3 offset = discOffset(vrl.direction, ctx.beamRadius, uDisc);
  // Near surfaces part of the disc lies behind them: an offset the beam's centre point cannot see falls back to the
  // centre (the kernel renormalised to the open side, so walls do not swallow the beam's energy).
  if (ctx.beamRadius > 0.0f) {
    const float len = glm::length(offset);
    if (len > 0.0f && ctx.embree.occluded(vrl.start + vrl.direction * v, offset / len, len)) offset = glm::vec3(0.0f);
  }
  const glm::vec3 start = vrl.start + offset;
  out.position = start + vrl.direction * v;
  // A beam's offset line crosses the media on its own; a VRL's transmittance comes from its entry (precomputed).
  // In a density grid the transmittance inside the medium is estimated along the line as well.
  const Medium& medium = ctx.scene.media[vrl.medium];
  const glm::vec3 tr = ctx.beamRadius > 0.0f || medium.heterogeneous()
                           ? ctx.embree.transmittance(start, vrl.direction, v)
                           : ctx.vrlEntry[static_cast<std::size_t>(&vrl - ctx.vrls.data())] *
                                 glm::exp(-medium.sigmaT() * std::max(0.0f, v - vrl.t0));
  out.weight = vrl.flux * medium.sigmaSAt(out.position) * tr / pdf;
  return true;
}

/// v along a VRL equiangularly around the point p (Kulla & Fajardo 2012): pdf h / ((B - A) (h^2 + (v - delta)^2)).
bool sampleVrlAroundPoint(const Context& ctx, const Vrl& vrl, const glm::vec3& p, Rng& rng, VrlPoint& out) {
  const EquiangularSpan span(vrl.start, vrl.direction, vrl.t0, vrl.t1, p, 1e-6f * ctx.sceneDiagonal);
  // Clamped against rounding at the span's ends: the pdf is that of the clamped v.
  const float v = std::clamp(span.at(rng.next1D()), vrl.t0, vrl.t1);
  return finishVrlPoint(ctx, vrl, v, span.pdf(v), rng, out);
}

/// v along a VRL with the two-line pdf ~ 1 / sqrt(h^2 + (v - v_c)^2 sin^2 theta) toward the camera line o + t d
/// (docs/theory.md §19), uniform for nearly parallel lines.
bool sampleVrlTowardLine(const Context& ctx, const Vrl& vrl, const glm::vec3& o, const glm::vec3& d, Rng& rng,
                         VrlPoint& out) {
  const float uV = rng.next1D();
  const glm::vec3& e = vrl.direction;
  const glm::vec3 w0 = vrl.start - o;
  const float b = glm::dot(d, e);
  const float sin2 = std::max(0.0f, 1.0f - b * b);
  const float sinT = std::sqrt(sin2);
  const float len = vrl.t1 - vrl.t0;
  if (!(len > 0.0f)) return false;
  if (sinT < kParallelSin) return finishVrlPoint(ctx, vrl, vrl.t0 + uV * len, 1.0f / len, rng, out);
  // Closest points: o + tc d and start + vc e.
  const float dd = glm::dot(d, w0), ee = glm::dot(e, w0);
  const float vc = (b * dd - ee) / sin2;
  const float tc = (dd - b * ee) / sin2;
  const float h = std::max(1e-6f * ctx.sceneDiagonal, glm::length(vrl.start + e * vc - (o + d * tc)));
  const float k = sinT / h;
  const float a0 = std::asinh((vrl.t0 - vc) * k), a1 = std::asinh((vrl.t1 - vc) * k);
  if (!(a1 > a0)) return finishVrlPoint(ctx, vrl, vrl.t0 + uV * len, 1.0f / len, rng, out);
  const float v = std::clamp(vc + std::sinh(a0 + uV * (a1 - a0)) / k, vrl.t0, vrl.t1);
  const float s = v - vc;
  const float pdf = sinT / ((a1 - a0) * std::sqrt(h * h + s * s * sin2));
  return finishVrlPoint(ctx, vrl, v, pdf, rng, out);
}

/// u along the camera ray equiangularly around p over [a, b); returns the medium interval holding it (or null) and
/// the weight sigma_s(u) T(o, u) / p(u).
const MediumInterval* sampleRayAroundPoint(const Context& ctx, const glm::vec3& o, const glm::vec3& d,
                                           const std::vector<MediumInterval>& intervals, float a, float b,
                                           const glm::vec3& p, float uT, float& tOut, glm::vec3& weightOut) {
  float pdf = 0.0f;
  const MediumInterval* in = sampleEquiangular(intervals, o, d, a, b, p, uT, 1e-6f * ctx.sceneDiagonal, tOut, pdf);
  if (!in) return nullptr;
  weightOut = ctx.scene.media[in->medium].sigmaSAt(o + d * tOut) *
              transmittanceAlong(ctx.scene.media, intervals, o, d, tOut) / pdf;
  return in;
}

/// Surface VPLs and VRLs lighting a surface point x (indirect light, without x's transmittance to the camera).
glm::vec3 indirectAtSurface(const Context& ctx, const Interaction& x, Rng& rng, Tally& tally) {
  // Surface VPLs: the exact transfer (no clamp), as renderVpl sums them (same order, same arithmetic).
  ShadowBatch vplBatch{ctx.embree, ctx.media, tally};
  for (uint32_t i : ctx.surfaceVpls) {
    const Vpl& vpl = ctx.vpls[i];
    const glm::vec3 c = vplContributionAt(x, vpl, ctx.vplBrdfs[i], 0.0f, kInfinity);
    ++tally.evaluations;
    if (!positive(c)) continue;
    vplBatch.add(ctx.embree.shadowRayBetween(x.position, x.offsetNormal(), vpl.position, vpl.geometricNormal), c);
  }
  vplBatch.flush();
  glm::vec3 result = vplBatch.sum;
  if (ctx.vrls.empty()) return result;
  // VRLs: v equiangular around x; one shadow ray from the VRL point to x.
  ShadowBatch vrlBatch{ctx.embree, true, tally};
  const float invSamples = 1.0f / static_cast<float>(ctx.vrlSamples);
  for (const Vrl& vrl : ctx.vrls) {
    const float g = ctx.scene.media[vrl.medium].g;
    for (int k = 0; k < ctx.vrlSamples; ++k) {
      VrlPoint p;
      ++tally.evaluations;
      if (!sampleVrlAroundPoint(ctx, vrl, x.position, rng, p)) continue;
      const glm::vec3 dv = p.position - x.position;
      const float dist2 = glm::dot(dv, dv);
      if (!(dist2 > 0.0f)) continue;
      const glm::vec3 wi = dv / std::sqrt(dist2);  // from x toward the VRL point
      const glm::vec3 fx = x.scatter(wi);          // f_r cos_x (zero from the back)
      if (!positive(fx)) continue;
      // At the VRL point light travelling along e leaves toward x (along -wi).
      const float fp = phaseHG(-wi, -vrl.direction, g);
      const glm::vec3 c = p.weight * fx * (fp * invSamples / dist2);
      if (!positive(c)) continue;
      ShadowRay ray = ctx.embree.shadowRayBetween(x.position, x.offsetNormal(), p.position, glm::vec3(0.0f));
      vrlBatch.add(ray, c);
    }
  }
  vrlBatch.flush();
  return result + vrlBatch.sum;
}

/// Surface VPLs and VRLs in-scattered along the camera ray's media part (indirect light), docs/theory.md §17, §19.
glm::vec3 indirectAlongRay(const Context& ctx, const glm::vec3& o, const glm::vec3& d,
                           const std::vector<MediumInterval>& intervals, float end, Rng& rng, Tally& tally) {
  const float a = intervals.front().t0;
  const float b = mediaSpanEnd(ctx.scene.media, intervals, end, ctx.sceneDiagonal);
  if (!(b > a)) return glm::vec3(0.0f);
  ShadowBatch batch{ctx.embree, true, tally};
  // Surface VPLs: one distance each, equiangular around the VPL.
  for (uint32_t i : ctx.surfaceVpls) {
    const Vpl& vpl = ctx.vpls[i];
    const float uT = rng.next1D();
    float t = 0.0f;
    glm::vec3 w;
    ++tally.evaluations;
    const MediumInterval* in = sampleRayAroundPoint(ctx, o, d, intervals, a, b, vpl.position, uT, t, w);
    if (!in) continue;
    const Interaction x = Interaction::inMediumAt(ctx.scene, o + d * t, in->medium, -d);
    const glm::vec3 c = vplContributionAt(x, vpl, ctx.vplBrdfs[i], 0.0f, kInfinity);
    if (!positive(c)) continue;
    batch.add(ctx.embree.shadowRayBetween(x.position, glm::vec3(0.0f), vpl.position, vpl.geometricNormal), c * w);
  }
  // VRLs: v by the two-line pdf, then u equiangular around x_v.
  const float invSamples = 1.0f / static_cast<float>(ctx.vrlSamples);
  for (const Vrl& vrl : ctx.vrls) {
    const float gv = ctx.scene.media[vrl.medium].g;
    for (int k = 0; k < ctx.vrlSamples; ++k) {
      VrlPoint p;
      ++tally.evaluations;
      if (!sampleVrlTowardLine(ctx, vrl, o, d, rng, p)) continue;
      const float uT = rng.next1D();
      float t = 0.0f;
      glm::vec3 w;
      const MediumInterval* in = sampleRayAroundPoint(ctx, o, d, intervals, a, b, p.position, uT, t, w);
      if (!in) continue;
      const glm::vec3 xu = o + d * t;
      const glm::vec3 dv = p.position - xu;
      const float dist2 = glm::dot(dv, dv);
      if (!(dist2 > 0.0f)) continue;
      const glm::vec3 wi = dv / std::sqrt(dist2);  // from x_u toward x_v
      const float fu = phaseHG(-d, wi, ctx.scene.media[in->medium].g);
      const float fv = phaseHG(-wi, -vrl.direction, gv);
      const glm::vec3 c = p.weight * w * (fu * fv * invSamples / dist2);
      if (!positive(c)) continue;
      batch.add(mediumRay(xu, p.position), c);
    }
  }
  batch.flush();
  return batch.sum;
}

/// Single scattering along the camera ray: one forced free flight (the conditioned free flight of the VPL render:
/// density proportional to mean_c sigma_t,c T_c(t) over the media intervals before `end`) and one equiangular distance
/// toward the light, MIS-weighted (medium_direct.h, docs/theory.md §24).
glm::vec3 singleScattering(const Context& ctx, const glm::vec3& o, const glm::vec3& d,
                           const std::vector<MediumInterval>& intervals, float end, Rng& rng) {
  return forcedFlightAlongRay(ctx.embree, ctx.lights, o, d, intervals, end, true, rng,
                              [](const Interaction&) { return glm::vec3(0.0f); });
}

/// One VRL (or beam) render of `set` with beam radius `radius` (0 = VRLs).
VplRenderResult renderWith(const OfflineScene& offline, const VplSet& set, const Settings& settings, float radius,
                           RenderControl* control, std::function<void(const Image& mean, int samplesSoFar)> onPass) {
  const Scene& scene = offline.scene();
  const EmbreeScene& embree = offline.embree();
  const LightSampler& lights = offline.lights();
  Context ctx{scene, embree, lights, set.vpls, set.vrls};
  ctx.vplBrdfs.reserve(set.vpls.size());
  for (std::size_t i = 0; i < set.vpls.size(); ++i) {
    const Vpl& v = set.vpls[i];
    ctx.vplBrdfs.push_back(brdfParamsAt(scene, v.material, v.uv));
    if (!v.inMedium) ctx.surfaceVpls.push_back(static_cast<uint32_t>(i));
  }
  ctx.vrlEntry.reserve(set.vrls.size());
  for (const Vrl& r : set.vrls) ctx.vrlEntry.push_back(embree.transmittance(r.start, r.direction, r.t0));
  ctx.media = scene.hasMedia();
  ctx.vrlSamples = std::max(1, settings.vrlSamples);
  ctx.beamRadius = radius;
  ctx.sceneDiagonal = std::max(scene.bounds.diagonal(), 1e-6f);

  const bool wantDirect = settings.components != Components::Indirect;
  const bool wantIndirect = settings.components != Components::Direct;
  const std::size_t pixels = static_cast<std::size_t>(std::max(0, settings.width)) * std::max(0, settings.height);
  std::vector<Tally> tallies(pixels);
  ProgressiveOptions options = progressiveOptions(settings, 1, std::move(onPass));

  PixelEstimator estimator = [&](int px, int py, uint32_t, Rng& rng) -> glm::vec3 {
    Tally& tally = tallies[static_cast<std::size_t>(py) * settings.width + px];
    const glm::vec3& camera = scene.camera.position;
    return manyLightCameraSample(
        embree, lights, settings, px, py, rng,
        [&](const glm::vec3& dir, const std::vector<MediumInterval>& intervals, float end) {
          // Single scattering, then surface VPLs and VRLs in-scattered along the ray (docs/theory.md §16-§19).
          glm::vec3 l(0.0f);
          if (wantDirect) l += singleScattering(ctx, camera, dir, intervals, end, rng);
          if (wantIndirect) l += indirectAlongRay(ctx, camera, dir, intervals, end, rng, tally);
          return l;
        },
        [&](const Interaction& sp) { return indirectAtSurface(ctx, sp, rng, tally); });
  };

  VplRenderResult result;
  static_cast<ProgressiveResult&>(result) = renderProgressive(options, estimator, control);
  for (const Tally& t : tallies) {
    result.shadowRays += t.shadowRays;
    result.vplEvaluations += t.evaluations;
  }
  result.clampEnergyRemoved = 0.0;
  return result;
}

}  // namespace

VplRenderResult renderVrl(const OfflineScene& offline, const VplSet& vpls, const Settings& settings,
                          RenderControl* control, std::function<void(const Image& mean, int samplesSoFar)> onPass) {
  return renderWith(offline, vpls, settings, 0.0f, control, std::move(onPass));
}

float beamRadiusForPass(const Settings& settings, float sceneDiagonal, int pass) {
  const float r1 = settings.beamRadius > 0.0f ? settings.beamRadius : 0.02f * sceneDiagonal;
  const float alpha = std::clamp(settings.beamShrink, 1e-6f, 1.0f);
  return r1 * std::pow(static_cast<float>(pass + 1), 0.5f * (alpha - 1.0f));
}

VplRenderResult renderVbl(const OfflineScene& offline, const Settings& settings, RenderControl* control,
                          std::function<void(const Image& mean, int samplesSoFar)> onPass) {
  const int passes = std::max(1, settings.beamPasses);
  const float diagonal = offline.scene().bounds.diagonal();
  VplRenderResult total;
  std::vector<glm::dvec3> sum;
  int samples = 0;
  for (int i = 0; i < passes; ++i) {
    if (control && control->cancelled()) {
      total.cancelled = true;
      break;
    }
    Settings s = settings;
    s.seed = settings.seed + static_cast<uint32_t>(i);
    // The inner render reports its fraction of the whole and stops when the caller cancels.
    RenderControl inner;
    inner.onProgress = [&, i](float f) {
      if (!control) return;
      if (control->cancelled()) inner.cancel = true;
      if (control->onProgress) control->onProgress((static_cast<float>(i) + f) / static_cast<float>(passes));
    };
    const VplSet set = generateVpls(offline, s, nullptr);
    VplRenderResult pass = renderWith(offline, set, s, beamRadiusForPass(settings, diagonal, i), &inner, {});
    if (pass.samplesPerPixel <= 0) {
      total.cancelled = true;
      break;
    }
    if (sum.empty()) sum.assign(pass.image.pixels.size(), glm::dvec3(0.0));
    for (std::size_t k = 0; k < sum.size(); ++k)
      sum[k] += glm::dvec3(pass.image.pixels[k]) * double(pass.samplesPerPixel);
    samples += pass.samplesPerPixel;
    total.seconds += pass.seconds;
    total.nonFiniteSamples += pass.nonFiniteSamples;
    total.shadowRays += pass.shadowRays;
    total.vplEvaluations += pass.vplEvaluations;
    total.image = Image(pass.image.width, pass.image.height);
    for (std::size_t k = 0; k < sum.size(); ++k) total.image.pixels[k] = glm::vec3(sum[k] / double(samples));
    total.samplesPerPixel = samples;
    if (onPass) onPass(total.image, samples);
    if (control && control->onProgress) control->onProgress(static_cast<float>(i + 1) / static_cast<float>(passes));
    if (pass.cancelled) {
      total.cancelled = true;
      break;
    }
  }
  if (total.image.empty()) total.image = Image(std::max(0, settings.width), std::max(0, settings.height));
  total.clampEnergyRemoved = 0.0;
  return total;
}

}  // namespace vplab
