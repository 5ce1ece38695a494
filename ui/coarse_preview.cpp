#include "ui/coarse_preview.h"

#include <algorithm>
#include <chrono>

namespace vplab::ui {

CoarsePreview::CoarsePreview() = default;
CoarsePreview::~CoarsePreview() = default;

Settings CoarsePreview::coarseSettings(const Settings& full) {
  Settings s = full;
  s.width = (full.width + 1) / 2;
  s.height = (full.height + 1) / 2;
  s.shadowMapSize = std::max(16, full.shadowMapSize / 2);
  return s;
}

Image CoarsePreview::render(const Scene& scene, const VplSet& vpls, const Settings& full, const Camera& camera) {
  const auto start = std::chrono::steady_clock::now();
  if (!renderer_) renderer_ = std::make_unique<PreviewRenderer>();
  renderer_->render(scene, vpls, coarseSettings(full), camera);
  Image image = resizedBilinear(renderer_->readLinear(), full.width, full.height);
  lastMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return image;
}

void CoarsePreview::invalidateScene() {
  if (renderer_) renderer_->invalidateScene();
}

void CoarsePreview::invalidateLights() {
  if (renderer_) renderer_->invalidateLights();
}

void CoarsePreview::invalidateVpls() {
  if (renderer_) renderer_->invalidateVpls();
}

}  // namespace vplab::ui
