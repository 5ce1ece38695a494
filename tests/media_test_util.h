#pragma once
// What the media tests compare with: the CPU images the GL tests render once for both backends, the lights' single
// scattering along camera rays as the VPL render draws it, and the media methods' mean light over many VPL sets.

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "renderer/core/sampling.h"
#include "renderer/image/image.h"
#include "renderer/image/metrics.h"
#include "renderer/offline/camera_sample.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/offline/vpl_renderer.h"
#include "renderer/offline/vrl_renderer.h"
#include "renderer/vpl/vpl_generation.h"

namespace vplab::test {

/// The CPU image of `key`, rendered by `render` the first time it is asked for (the backends' tests share it).
inline const Image& cachedCpu(const std::string& key, const std::function<Image()>& render) {
  static std::map<std::string, Image> images;
  auto it = images.find(key);
  if (it == images.end()) it = images.emplace(key, render()).first;
  return it->second;
}

/// The CPU's single scattering of the lights along camera rays: per pixel sample, one forced free flight in the media
/// before the surface (ratio tracking through a grid) and the reference's direct-light estimator there
/// (renderer/offline/camera_sample.h, as the VPL render draws it), nothing else.
inline Image cpuSingleScattering(const OfflineScene& l, const Settings& s, int spp) {
  const Scene& scene = l.scene();
  Image image(s.width, s.height);
  std::vector<MediumInterval> intervals;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      Rng rng(hashKey(static_cast<uint64_t>(y) * s.width + x, 0x73696e676c65ull));
      glm::vec3 sum(0.0f);
      for (int i = 0; i < spp; ++i) {
        const glm::vec2 jitter = rng.next2D();
        const glm::vec3 dir = cameraRayDirection(scene.camera, static_cast<float>(x) + jitter.x,
                                                 static_cast<float>(y) + jitter.y, s.width, s.height);
        const auto hit = l.embree().intersect(scene.camera.position, dir);
        const float end = hit ? hit->distance : kInfinity;
        mediumIntervals(scene.media, scene.camera.position, dir, end, intervals);
        float t = 0.0f;
        uint32_t medium = 0;
        glm::vec3 weight(0.0f);
        if (intervals.empty() || !sampleForcedFlight(scene.media, intervals, scene.camera.position, dir, end,
                                                     rng.next2D(), t, medium, weight))
          continue;
        const Interaction at = Interaction::inMediumAt(scene, scene.camera.position + dir * t, medium, -dir);
        sum += weight * estimateDirectLight(l.embree(), l.lights(), at, rng);
      }
      image.at(x, y) = sum / static_cast<float>(spp);
    }
  return image;
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
