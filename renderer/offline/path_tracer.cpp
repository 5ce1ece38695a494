#include "renderer/offline/path_tracer.h"

#include "renderer/offline/direct_light.h"
#include "renderer/offline/interaction.h"
#include "renderer/offline/medium_direct.h"
#include "renderer/offline/spectral_mis.h"
#include "renderer/scene/brdf_params.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <vector>

namespace vplab {

namespace {

bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// A vertex's next direction in media with point lights: with probability LightSampler::kTowardPointLights toward
/// them, else from the BRDF or phase function; the weight and pdf are those of the mixture (one-sample MIS, the balance
/// heuristic over the two samplers). Draws one number, then the chosen sampler's.
Interaction::Sample sampleMixedDirection(const Interaction& vertex, const LightSampler& lights, Rng& rng) {
  const float q = LightSampler::kTowardPointLights;
  const float u = rng.next1D();
  Interaction::Sample s;
  if (u < q) {
    const glm::vec2 uCone = rng.next2D();
    if (!lights.sampleTowardPointLights(vertex.position, glm::vec3(u / q, uCone), s.wi)) return {};
  } else {
    s = vertex.sample(rng);
    if (!s.valid()) return {};
  }
  const glm::vec3 f = vertex.scatter(s.wi);
  const float pdf = lights.mixedScatterPdf(vertex.position, s.wi, vertex.pdf(s.wi));
  if (!(pdf > 0.0f) || !(f.r > 0.0f || f.g > 0.0f || f.b > 0.0f)) return {};
  s.pdf = pdf;
  s.weight = f / pdf;
  return s;
}

}  // namespace

glm::vec3 referenceRadiance(const EmbreeScene& embree, const LightSampler& lights, const glm::vec3& origin,
                            const glm::vec3& direction, int maxDepth, Components components, Rng& rng,
                            ReferenceStats* stats, DistanceSampling distanceSampling) {
  const Scene& scene = embree.scene();
  const bool wantDirect = components != Components::Indirect;
  const bool wantIndirect = components != Components::Direct;
  // A Direct-only render never needs vertices past the first reflection or scattering event.
  const int lastBounce = wantIndirect ? maxDepth : std::min(maxDepth, 1);
  // Free flights draw their two numbers only on segments that cross a medium (EmbreeScene::traceSegment); every
  // flight of the path samples the same channel, weighted by spectral MIS over the whole path.
  PathSpectralMis spectral;
  auto draw = [&rng, &spectral]() { return spectral.draw(rng.next2D()); };
  constexpr float kUnbounded = std::numeric_limits<float>::infinity();

  uint64_t shadowRays = 0, bounceRays = 0;
  glm::vec3 radiance(0.0f);
  glm::vec3 throughput(1.0f);
  glm::vec3 dir = direction;

  // Distance sampling toward the lights on a segment that crossed a medium (docs/theory.md §24): the segment's
  // equiangular estimate of the lights' single scattering, added with the throughput before the segment, and the
  // context the free flight's vertex weights its next-event estimate with. `vertexBounce` is the bounce its
  // scattering vertex would be: only segments whose vertex is counted draw and estimate anything.
  MediumLightSegment along(embree, origin, direction, 0.0f, false, glm::vec3(1.0f), distanceSampling,
                           lights.hasPointLights());
  // In media with point or spot lights, directions are also sampled toward those lights (mixedScatterPdf): a segment
  // passing at h from a point light carries an equiangular estimate of about 1/h, which phase and BRDF sampling
  // alone leave as fireflies of multiple scattering (docs/theory.md §24).
  const bool mixed = lights.hasPointLights();
  auto lightsAlong = [&](const glm::vec3& from, const glm::vec3& w, const Segment& s, int vertexBounce) {
    along.clear();
    if (!s.crossedMedium || vertexBounce > lastBounce) return;
    along.reset(from, w, s.surfaceDistance, spectral.pdf);
    const glm::vec3 l = along.equiangular(lights, rng, &shadowRays);
    if (vertexBounce == 1 ? wantDirect : wantIndirect) radiance += throughput * l;
  };

  // Primary ray; emission seen directly belongs to the Direct component (zero reflections). Through media the
  // segment ends at the surface or at a scattering event, with the free flight's weight.
  Segment segment = embree.traceSegment(origin, dir, kUnbounded, draw);
  lightsAlong(origin, dir, segment, 1);
  if (segment.crossedMedium) spectral.apply(segment, throughput);
  if (segment.end == Segment::End::Surface && wantDirect)
    radiance += throughput * lights.emittedRadiance(segment.hit->triangle, segment.hit->geometricNormal,
                                                    segment.hit->uv, -dir);

  // Vertex `bounce` is the bounce-th reflection or scattering event: light leaving it toward the camera has
  // interacted `bounce` times, so bounce 1 feeds Direct and bounces >= 2 feed Indirect.
  for (int bounce = 1; segment.end != Segment::End::Escape && bounce <= lastBounce; ++bounce) {
    const Interaction vertex = Interaction::atSegmentEnd(scene, segment, -dir);
    // One-sided surfaces: the back of a surface reflects nothing (and the path ends there).
    if (!vertex.scatters()) break;
    const bool count = bounce == 1 ? wantDirect : wantIndirect;

    // Next-event estimation with MIS (Veach 1997, eq. 9.13, power heuristic): the light-sampling strategy, through
    // the media's transmittance. When this bounce is not wanted its three random numbers are still drawn, so the
    // stream (and every later vertex) does not depend on the components asked for.
    // A medium vertex weights its estimate against the equiangular one of the segment that found it.
    if (count) {
      const MediumLightSegment* distanceMis = vertex.inMedium && along.overlapsMedia() ? &along : nullptr;
      radiance += throughput * sampleLightDirect(embree, lights, vertex, rng, &shadowRays, distanceMis, mixed);
    } else {
      rng.next1D();
      rng.next2D();
    }

    // BRDF or phase-function sampling: the next direction of the walk, and the second MIS strategy for the next
    // vertex's emission.
    const Interaction::Sample bs = mixed ? sampleMixedDirection(vertex, lights, rng) : vertex.sample(rng);
    if (!bs.valid()) break;
    // Path throughput update: beta *= f cos / pdf (f_p / pdf, exactly 1 in a medium unless the direction was drawn
    // from the mixture with the point lights).
    throughput *= bs.weight;
    // A non-finite throughput is a defect of a BRDF or pdf: the sample becomes NaN, which renderProgressive leaves
    // out of the mean and counts, instead of a silently shortened path.
    if (!finite3(throughput)) {
      radiance = glm::vec3(std::numeric_limits<float>::quiet_NaN());
      break;
    }

    const glm::vec3 next = vertex.rayOrigin(embree, bs.wi);
    Segment nextSegment = embree.traceSegment(next, bs.wi, kUnbounded, draw);
    ++bounceRays;
    // The lights' single scattering along the new segment, escaping or not, by equiangular sampling (MIS).
    lightsAlong(next, bs.wi, nextSegment, bounce + 1);
    if (nextSegment.end == Segment::End::Escape) break;
    // Free-flight sampling: T sigma_s / pdf for a scattering event, T / P(no event) for the surface.
    if (nextSegment.crossedMedium) spectral.apply(nextSegment, throughput);
    // Emission found by the sampled ray, MIS-weighted against the light pdf next-event estimation used at this
    // vertex: it has interacted `bounce` times, like the NEE term above.
    if (count && nextSegment.end == Segment::End::Surface)
      radiance += throughput * misWeightedEmission(lights, vertex.position, *nextSegment.hit, bs.wi, bs.pdf);

    // Russian roulette on the throughput (Arvo & Kirk 1990): survive with probability q, divide by q to stay
    // unbiased. The draw happens at every bounce past the start so the stream stays component-independent.
    if (bounce >= kRussianRouletteStartBounce) {
      float uRr = rng.next1D();
      float q = std::min(0.95f, std::max({throughput.r, throughput.g, throughput.b}));
      if (!(q > 0.0f) || uRr >= q) break;
      throughput /= q;
    }
    dir = bs.wi;
    segment = std::move(nextSegment);
  }

  if (stats) {
    stats->cameraRays += 1;
    stats->bounceRays += bounceRays;
    stats->shadowRays += shadowRays;
  }
  return radiance;
}

ProgressiveResult renderReference(const OfflineScene& offline, const Settings& settings, RenderControl* control,
                                  std::function<void(const Image& mean, int samplesSoFar)> onPass,
                                  ReferenceStats* stats) {
  const Scene& scene = offline.scene();
  const EmbreeScene& embree = offline.embree();
  const LightSampler& lights = offline.lights();
  requireValidSettings(settings);

  // About 32 passes: frequent enough to watch, few enough that the per-pass bookkeeping stays negligible.
  ProgressiveOptions options =
      progressiveOptions(settings, std::clamp(settings.samplesPerPixel / 32, 1, 16), std::move(onPass));

  if (lights.empty()) {
    // Nothing emits: the exact answer is black, no need to trace anything.
    ProgressiveResult black;
    black.image = Image(settings.width, settings.height);
    black.samplesPerPixel = settings.samplesPerPixel;
    if (control && control->onProgress) control->onProgress(1.0f);
    if (options.onPass) options.onPass(black.image, black.samplesPerPixel);
    return black;
  }

  // Per-pixel counters: a row is handled by one thread at a time, so no atomics and no shared cache lines.
  std::vector<ReferenceStats> perPixel(stats ? static_cast<std::size_t>(settings.width) * settings.height : 0);
  const Camera& camera = scene.camera;
  const int maxDepth = settings.maxDepth;
  const Components components = settings.components;
  const int width = settings.width, height = settings.height;

  PixelEstimator estimator = [&](int x, int y, uint32_t, Rng& rng) {
    // Box pixel filter: a uniformly jittered position inside the pixel.
    glm::vec2 jitter = rng.next2D();
    glm::vec3 dir = cameraRayDirection(camera, static_cast<float>(x) + jitter.x, static_cast<float>(y) + jitter.y,
                                       width, height);
    ReferenceStats* s = stats ? &perPixel[static_cast<std::size_t>(y) * width + x] : nullptr;
    return referenceRadiance(embree, lights, camera.position, dir, maxDepth, components, rng, s);
  };
  ProgressiveResult result = renderProgressive(options, estimator, control);

  if (stats) {
    *stats = ReferenceStats{};
    for (const ReferenceStats& p : perPixel) {
      stats->cameraRays += p.cameraRays;
      stats->bounceRays += p.bounceRays;
      stats->shadowRays += p.shadowRays;
    }
  }
  return result;
}

}  // namespace vplab
