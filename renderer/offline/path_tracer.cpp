#include "renderer/offline/path_tracer.h"

#include "renderer/offline/direct_light.h"
#include "renderer/offline/interaction.h"
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

}  // namespace

glm::vec3 referenceRadiance(const EmbreeScene& embree, const LightSampler& lights, const glm::vec3& origin,
                            const glm::vec3& direction, int maxDepth, Components components, Rng& rng,
                            ReferenceStats* stats) {
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

  // Primary ray; emission seen directly belongs to the Direct component (zero reflections). Through media the
  // segment ends at the surface or at a scattering event, with the free flight's weight.
  Segment segment = embree.traceSegment(origin, dir, kUnbounded, draw);
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
    if (count) {
      radiance += throughput * sampleLightDirect(embree, lights, vertex, rng, &shadowRays);
    } else {
      rng.next1D();
      rng.next2D();
    }

    // BRDF or phase-function sampling: the next direction of the walk, and the second MIS strategy for the next
    // vertex's emission.
    const Interaction::Sample bs = vertex.sample(rng);
    if (!bs.valid()) break;
    // Path throughput update: beta *= f cos / pdf (f_p / pdf = 1 in a medium).
    if (!vertex.inMedium) throughput *= bs.weight;
    // A non-finite throughput is a defect of a BRDF or pdf: the sample becomes NaN, which renderProgressive leaves
    // out of the mean and counts, instead of a silently shortened path.
    if (!finite3(throughput)) {
      radiance = glm::vec3(std::numeric_limits<float>::quiet_NaN());
      break;
    }

    const glm::vec3 next = vertex.rayOrigin(embree, bs.wi);
    Segment nextSegment = embree.traceSegment(next, bs.wi, kUnbounded, draw);
    ++bounceRays;
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
