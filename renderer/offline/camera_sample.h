#pragma once
// One camera sample of an exact many-light render (docs/theory.md §1, §16), the skeleton every such method shares:
// a primary ray through a jittered pixel position; through media, the light in-scattered along it and the surface's
// light attenuated by the transmittance to it; at the surface, emission and the direct light (the reference's own
// estimators) and the method's indirect light. The methods differ only in the two callbacks:
//   alongRay(intervals, end) -> radiance the media send along the ray (direct and indirect, as the components ask);
//   atSurface(interaction)   -> indirect light reflected at the surface toward the camera.
// Random numbers are drawn in this order: jitter, alongRay's, the direct light's, atSurface's.

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <optional>
#include <vector>

#include "renderer/offline/direct_light.h"
#include "renderer/offline/embree_scene.h"
#include "renderer/offline/interaction.h"
#include "renderer/offline/light_sampler.h"
#include "renderer/offline/media_tracking.h"
#include "renderer/offline/progressive.h"
#include "renderer/scene/medium.h"
#include "renderer/settings.h"

namespace vplab {

/// The far end of a camera ray's media span before `end`: a span reaching infinity (a medium filling all space) is cut
/// where the least attenuated channel's transmittance is 1e-6, or at 1000 scene diagonals for a channel that does not
/// attenuate (the lights' 1/d^2 has faded long before).
inline float mediaSpanEnd(const std::vector<Medium>& media, const std::vector<MediumInterval>& intervals, float end,
                          float sceneDiagonal) {
  float b = std::min(intervals.back().t1, end);
  if (!std::isfinite(b)) {
    const glm::vec3 st = media[intervals.back().medium].sigmaT();
    const float least = std::min({st.x, st.y, st.z});
    b = intervals.back().t0 + (least > 0.0f ? 14.0f / least : 1000.0f * sceneDiagonal);
  }
  return b;
}

/// A distance t along o + t d in [a, b), drawn equiangularly around the point p (Kulla & Fajardo 2012):
/// t = delta + h tan(theta), theta uniform between the span's angles, pdf h / ((thetaB - thetaA)(h^2 + (t - delta)^2)),
/// which cancels a 1/d^2 toward p. h is at least minH. Returns the interval holding t (null between boxes or when the
/// sample is degenerate), with tOut and pdfOut.
/// The equiangular parametrisation of [a, b) on o + t d around p: delta, the foot of p on the line, h, p's distance
/// from it (at least minH), and the span's angles seen from p.
struct EquiangularSpan {
  float delta, h, thetaA, thetaB;
  EquiangularSpan(const glm::vec3& o, const glm::vec3& d, float a, float b, const glm::vec3& p, float minH)
      : delta(glm::dot(p - o, d)),
        h(std::max(minH, glm::length(o + d * delta - p))),
        thetaA(std::atan2(a - delta, h)),
        thetaB(std::atan2(b - delta, h)) {}
  float at(float u) const { return delta + h * std::tan(thetaA + u * (thetaB - thetaA)); }
  float pdf(float t) const { return h / ((thetaB - thetaA) * (h * h + (t - delta) * (t - delta))); }
};

inline const MediumInterval* sampleEquiangular(const std::vector<MediumInterval>& intervals, const glm::vec3& o,
                                               const glm::vec3& d, float a, float b, const glm::vec3& p, float u,
                                               float minH, float& tOut, float& pdfOut) {
  const EquiangularSpan span(o, d, a, b, p, minH);
  const float t = span.at(u);
  const float pdf = span.pdf(t);
  if (!(pdf > 0.0f) || !std::isfinite(t) || !std::isfinite(pdf)) return nullptr;
  const MediumInterval* in = nullptr;
  for (const MediumInterval& iv : intervals)
    if (t >= iv.t0 && t < iv.t1) in = &iv;
  tOut = t;
  pdfOut = pdf;
  return in;
}

/// The density with which sampleEquiangular() draws t (0 outside [a, b)): the same span, so the sampled t gets
/// exactly the pdf sampleEquiangular() returned.
inline float equiangularPdf(const glm::vec3& o, const glm::vec3& d, float a, float b, const glm::vec3& p, float minH,
                            float t) {
  if (!(t >= a) || !(t < b)) return 0.0f;
  const float pdf = EquiangularSpan(o, d, a, b, p, minH).pdf(t);
  return pdf > 0.0f && std::isfinite(pdf) ? pdf : 0.0f;
}

template <class AlongRay, class AtSurface>
glm::vec3 manyLightCameraSample(const EmbreeScene& embree, const LightSampler& lights, const Settings& settings, int x,
                                int y, Rng& rng, AlongRay&& alongRay, AtSurface&& atSurface) {
  const Scene& scene = embree.scene();
  const bool wantDirect = settings.components != Components::Indirect;
  const bool wantIndirect = settings.components != Components::Direct;
  // Step 1: primary ray through a jittered pixel position.
  const glm::vec2 jitter = rng.next2D();
  const glm::vec3 dir = cameraRayDirection(scene.camera, static_cast<float>(x) + jitter.x,
                                           static_cast<float>(y) + jitter.y, settings.width, settings.height);
  const std::optional<SurfaceHit> hit = embree.intersect(scene.camera.position, dir);
  // Step 2: through media, the in-scattered light along the ray and the transmittance to the surface.
  glm::vec3 radiance(0.0f);
  glm::vec3 toSurface(1.0f);
  const bool media = embree.hasMedia();
  if (media) {
    static thread_local std::vector<MediumInterval> intervals;
    const float end = hit ? hit->distance : kInfinity;
    mediumIntervals(scene.media, scene.camera.position, dir, end, intervals);
    if (!intervals.empty()) {
      radiance += alongRay(dir, intervals, end);
      toSurface = transmittanceAlong(scene.media, intervals, scene.camera.position, dir, end);
    }
  }
  if (!hit) return radiance;
  const Interaction sp = Interaction::onSurface(scene, *hit, -dir);
  glm::vec3 surface(0.0f);
  // Step 3: emission seen directly, as the reference counts it (one-sided emitters).
  if (wantDirect) surface += lights.emittedRadiance(hit->triangle, hit->geometricNormal, hit->uv, sp.wo);
  if (!sp.scatters()) return radiance + surface * toSurface;
  // Step 4: direct light, the reference's estimator (next-event estimation + BRDF sampling, MIS).
  if (wantDirect) surface += estimateDirectLight(embree, lights, sp.hit, sp.wo, sp.brdf, rng);
  // Step 5: the method's indirect light.
  if (wantIndirect) surface += atSurface(sp);
  return media ? radiance + surface * toSurface : surface;
}

}  // namespace vplab
