#include "renderer/vpl/vpl_importance.h"

#include "renderer/offline/progressive.h"
#include "renderer/scene/brdf_params.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace vplab {

namespace {

/// Shadow rays per occlusion batch.
constexpr std::size_t kImportanceBatch = 64;

}  // namespace

std::vector<ShadingPoint> importancePoints(const OfflineScene& offline, const Settings& settings) {
  return importancePoints(offline, offline.scene().camera, settings.importancePoints, settings.width, settings.height);
}

std::vector<ShadingPoint> importancePoints(const OfflineScene& offline, const Camera& camera, int count, int width,
                                           int height) {
  const Scene& scene = offline.scene();
  const EmbreeScene& embree = offline.embree();
  std::vector<ShadingPoint> points;
  const int m = std::max(1, count);
  const float aspect = static_cast<float>(width) / static_cast<float>(std::max(1, height));
  // A grid of about m cells with the image's aspect ratio; one primary ray through each cell centre.
  int gx = std::max(1, static_cast<int>(std::lround(std::sqrt(static_cast<double>(m) * aspect))));
  int gy = std::max(1, static_cast<int>(std::lround(static_cast<double>(m) / gx)));
  points.reserve(static_cast<std::size_t>(gx) * gy);
  for (int j = 0; j < gy; ++j)
    for (int i = 0; i < gx; ++i) {
      float px = (static_cast<float>(i) + 0.5f) / gx * static_cast<float>(width);
      float py = (static_cast<float>(j) + 0.5f) / gy * static_cast<float>(height);
      glm::vec3 dir = cameraRayDirection(camera, px, py, width, height);
      std::optional<SurfaceHit> hit = embree.intersect(camera.position, dir);
      if (!hit || glm::dot(hit->geometricNormal, -dir) <= 0.0f) continue;
      ShadingPoint sp;
      sp.hit = *hit;
      sp.wo = -dir;
      sp.brdf = brdfParamsAt(scene, hit->material, hit->uv);
      points.push_back(sp);
    }
  return points;
}

ImportanceEstimator::ImportanceEstimator(const OfflineScene& offline, const Settings& settings)
    : scene_(offline.scene()), embree_(offline.embree()), points_(importancePoints(offline, settings)) {
  const float d = kImportanceDistanceFraction * std::max(scene_.bounds.diagonal(), 1e-6f);
  bound_ = 1.0f / (d * d);
}

double ImportanceEstimator::operator()(const Vpl& vpl) const {
  if (points_.empty()) return 0.0;
  BrdfParams vplBrdf = brdfParamsAt(scene_, vpl.material, vpl.uv);
  std::array<ShadowRay, kImportanceBatch> rays;
  std::array<float, kImportanceBatch> values;
  std::array<uint8_t, kImportanceBatch> blocked;
  double sum = 0.0;
  std::size_t n = 0;
  auto flush = [&]() {
    embree_.occludedBatch(rays.data(), blocked.data(), n);
    for (std::size_t i = 0; i < n; ++i)
      if (!blocked[i]) sum += values[i];
    n = 0;
  };
  for (const ShadingPoint& sp : points_) {
    float lum = luminance(vplUnoccludedContribution(sp, vpl, vplBrdf, bound_));
    if (!(lum > 0.0f) || !std::isfinite(lum)) continue;
    rays[n] = embree_.shadowRayBetween(sp.hit.position, sp.hit.geometricNormal, vpl.position, vpl.geometricNormal);
    values[n] = lum;
    ++n;
    if (n == kImportanceBatch) flush();
  }
  if (n > 0) flush();
  return sum / static_cast<double>(points_.size());
}

}  // namespace vplab
