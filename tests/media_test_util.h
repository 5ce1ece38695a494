#pragma once
// What the media tests compare with: the CPU images the GL tests render once for both backends, the lights' single
// scattering along camera rays as the VPL render draws it, and the media methods' mean light over many VPL sets.

#include <string>
#include <vector>

#include "renderer/core/parallel.h"
#include "renderer/core/sampling.h"
#include "renderer/image/image.h"
#include "renderer/image/metrics.h"
#include "renderer/offline/camera_sample.h"
#include "renderer/offline/medium_direct.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/offline/vpl_renderer.h"
#include "renderer/offline/vrl_renderer.h"
#include "renderer/vpl/vpl_generation.h"

namespace vplab::test {

/// Per pixel `spp` jittered camera rays, each adding alongRay(o, d, intervals, end, rng) for the media intervals
/// before its first surface (nothing for a ray that crosses no medium): the media part of a camera sample alone.
template <class AlongRay>
Image cpuAlongCameraRays(const OfflineScene& l, const Settings& s, int spp, uint64_t salt, AlongRay&& alongRay) {
  const Scene& scene = l.scene();
  Image image(s.width, s.height);
  // A row per work item on the settings' threads; each pixel's random numbers are its own.
  parallelFor(s.height, resolveThreadCount(s.threads), [&](int64_t row, int) {
    const int y = static_cast<int>(row);
    std::vector<MediumInterval> intervals;
    for (int x = 0; x < s.width; ++x) {
      Rng rng(hashKey(static_cast<uint64_t>(y) * s.width + x, salt));
      glm::vec3 sum(0.0f);
      for (int i = 0; i < spp; ++i) {
        const glm::vec2 jitter = rng.next2D();
        const glm::vec3 dir = cameraRayDirection(scene.camera, static_cast<float>(x) + jitter.x,
                                                 static_cast<float>(y) + jitter.y, s.width, s.height);
        const auto hit = l.embree().intersect(scene.camera.position, dir);
        const float end = hit ? hit->distance : kInfinity;
        mediumIntervals(scene.media, scene.camera.position, dir, end, intervals);
        if (!intervals.empty()) sum += alongRay(scene.camera.position, dir, intervals, end, rng);
      }
      image.at(x, y) = sum / static_cast<float>(spp);
    }
  });
  return image;
}

/// The light of one forced free flight per pixel sample in the media before the surface (ratio tracking through a
/// grid), as the VPL render draws its camera rays' compensation (renderer/offline/vpl_renderer.cpp, mediumAlongRay,
/// step 1): the flight's weight times `at(x, rng)`, the radiance leaving the medium point x toward the camera.
/// Nothing else: no surfaces, no VPLs' in-scattering.
template <class AtMediumPoint>
Image cpuForcedFlights(const OfflineScene& l, const Settings& s, int spp, uint64_t salt, AtMediumPoint&& at) {
  const Scene& scene = l.scene();
  return cpuAlongCameraRays(
      l, s, spp, salt,
      [&](const glm::vec3& o, const glm::vec3& dir, const std::vector<MediumInterval>& intervals, float end, Rng& rng) {
        float t = 0.0f;
        uint32_t medium = 0;
        glm::vec3 weight(0.0f);
        if (!sampleForcedFlight(scene.media, intervals, o, dir, end, rng.next2D(), t, medium, weight))
          return glm::vec3(0.0f);
        return weight * at(Interaction::inMediumAt(scene, o + dir * t, medium, -dir), rng);
      });
}

/// The CPU's single scattering of the lights along camera rays, as the VPL and VRL renders draw it
/// (renderer/offline/medium_direct.h, forcedFlightAlongRay: a forced flight and an equiangular distance, MIS), nothing
/// else.
inline Image cpuSingleScattering(const OfflineScene& l, const Settings& s, int spp) {
  return cpuAlongCameraRays(
      l, s, spp, 0x73696e676c65ull,
      [&](const glm::vec3& o, const glm::vec3& dir, const std::vector<MediumInterval>& intervals, float end, Rng& rng) {
        return forcedFlightAlongRay(l.embree(), l.lights(), o, dir, intervals, end, true, rng,
                                    [](const Interaction&) { return glm::vec3(0.0f); });
      });
}

/// The medium's part of the residual's compensation in a CPU VPL render of `method` (VplAbc: Engelhardt et al.'s
/// approximate one; VplKK: Raab et al.'s) on `vpls` with the settings' bound: the method's compensation at each forced
/// flight along the camera rays, exactly what renderVpl adds in the media besides the bounded light, nothing else.
inline Image cpuMediumCompensation(const OfflineScene& l, const VplSet& vpls, Method method, const Settings& s,
                                   int spp) {
  const VplTransport transport(l, vpls, method, s);
  return cpuForcedFlights(l, s, spp, 0x636f6d70656eull, [&](const Interaction& at, Rng& rng) {
    GatherTally tally;
    return transport.methodCompensation(at, rng, tally);
  });
}

/// The media's exact part of a furnace image's mean, per channel: in a closed furnace whose walls hold radiance 2
/// everywhere (test::makeFurnaceBox(0.5)), a pixel gets 2 T from the walls (T its camera ray's transmittance to the
/// first surface) and 2 (1 - T) from the media's in-scattering (a non-absorbing medium in a uniform field scatters in
/// what it scatters out). T exactly, averaged over the width x height pixels at 4 x 4 stratified positions each.
inline glm::dvec3 furnaceMediumPart(const OfflineScene& l, int width, int height) {
  constexpr int kRays = 4;
  const Scene& scene = l.scene();
  std::vector<MediumInterval> intervals;
  glm::dvec3 transmittance(0.0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int j = 0; j < kRays; ++j)
        for (int i = 0; i < kRays; ++i) {
          const glm::vec3 dir =
              cameraRayDirection(scene.camera, x + (i + 0.5f) / kRays, y + (j + 0.5f) / kRays, width, height);
          const auto hit = l.embree().intersect(scene.camera.position, dir);
          const float end = hit ? hit->distance : kInfinity;
          mediumIntervals(scene.media, scene.camera.position, dir, end, intervals);
          transmittance +=
              intervals.empty()
                  ? glm::dvec3(1.0)
                  : glm::dvec3(transmittanceAlong(scene.media, intervals, scene.camera.position, dir, end));
        }
  transmittance /= static_cast<double>(width) * height * kRays * kRays;
  return 2.0 * (1.0 - transmittance);
}

/// The media methods' mean luminance (as the bound's removed share is measured) over `sets` VPL sets (seeds firstSeed, firstSeed + 1, ...) at 2 pixel samples each,
/// with the settings' size, VPL count and components; the bound's ball is a tenth of the scene's diagonal.
struct MediaMethodMeans {
  double unbounded = 0.0, bounded = 0.0, removed = 0.0, kk = 0.0, abc = 0.0, vrl = 0.0;
};
inline MediaMethodMeans mediaMethodMeans(const OfflineScene& scene, const Settings& settings, int sets,
                                         uint32_t firstSeed, bool withUnbounded, bool withVrl) {
  const float diagonal = scene.scene().geometryBounds.diagonal();
  MediaMethodMeans m;
  for (int i = 0; i < sets; ++i) {
    Settings v = settings;
    v.samplesPerPixel = 2;
    v.seed = firstSeed + static_cast<uint32_t>(i);
    const VplSet vpls = generateVpls(scene, v);
    if (withUnbounded) m.unbounded += meanLuminance(renderVpl(scene, vpls, Method::Vpl, v).image) / sets;
    if (withVrl) m.vrl += meanLuminance(renderVrl(scene, vpls, v).image) / sets;
    v.clampBound = 1.0f / (0.1f * diagonal * 0.1f * diagonal);
    const VplRenderResult c = renderVpl(scene, vpls, Method::Vpl, v);
    m.bounded += meanLuminance(c.image) / sets;
    m.removed += c.clampEnergyRemoved / sets;
    m.kk += meanLuminance(renderVpl(scene, vpls, Method::VplKK, v).image) / sets;
    m.abc += meanLuminance(renderVpl(scene, vpls, Method::VplAbc, v).image) / sets;
  }
  return m;
}

}  // namespace vplab::test
