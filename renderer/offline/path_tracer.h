#pragma once
// The path-traced reference (docs/theory.md §10, §16): the ground truth every many-light method is measured
// against. Unidirectional path tracing with next-event estimation and MIS against BRDF sampling at every vertex,
// Russian roulette on the throughput, one-sided emitters and a box pixel filter. Through participating media every
// segment samples a free flight (spectral MIS over the RGB channels, so chromatic media stay unbiased), scattering
// vertices sample the Henyey-Greenstein phase function (MIS against next-event estimation) and every shadow ray
// carries the media's transmittance.

#include "renderer/core/parallel.h"
#include "renderer/offline/embree_scene.h"
#include "renderer/offline/light_sampler.h"
#include "renderer/offline/medium_direct.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/offline/progressive.h"
#include "renderer/scene/scene.h"
#include "renderer/settings.h"

#include <cstdint>
#include <functional>

namespace vplab {

/// Bounce after which Russian roulette may end a path (earlier bounces carry most of the energy).
inline constexpr int kRussianRouletteStartBounce = 3;

/// What a reference render traced, for rays/s figures.
struct ReferenceStats {
  uint64_t cameraRays = 0;
  uint64_t bounceRays = 0;  ///< closest-hit rays after BRDF sampling
  uint64_t shadowRays = 0;
  uint64_t totalRays() const { return cameraRays + bounceRays + shadowRays; }
};

/// Radiance arriving at the camera along one primary ray, restricted to `components`: Direct is emission seen
/// directly plus light after exactly one reflection or scattering event (single scattering in media); Indirect is
/// every path with two or more.
/// The random numbers drawn do not depend on `components`, so Direct + Indirect equals All sample by sample.
/// Every segment through media adds the lights' single scattering by equiangular sampling toward the light that
/// next-event estimation picks, combined with the free flight by MIS (distanceSampling: both, or one alone for tests;
/// docs/theory.md §24).
/// NaN when the path's throughput became non-finite (renderProgressive counts such samples).
glm::vec3 referenceRadiance(const EmbreeScene& embree, const LightSampler& lights, const glm::vec3& origin,
                            const glm::vec3& direction, int maxDepth, Components components, Rng& rng,
                            ReferenceStats* stats = nullptr, DistanceSampling distanceSampling = DistanceSampling::Mis);

/// Renders settings.width x settings.height at settings.samplesPerPixel (seed, threads, maxDepth, components from
/// settings). onPass (may be empty) sees the running mean after each progressive pass. With no lights the image is
/// black and nothing is traced. stats, when given, receives the ray counts of everything traced.
ProgressiveResult renderReference(const OfflineScene& offline, const Settings& settings,
                                  RenderControl* control = nullptr,
                                  std::function<void(const Image& mean, int samplesSoFar)> onPass = {},
                                  ReferenceStats* stats = nullptr);

}  // namespace vplab
