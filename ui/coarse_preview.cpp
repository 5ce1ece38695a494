#include "ui/coarse_preview.h"

#include <algorithm>

#include "ui/change_timer.h"

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
  const double start = steadySeconds();
  if (!renderer_) renderer_ = std::make_unique<PreviewRenderer>();
  renderer_->render(scene, vpls, coarseSettings(full), camera);
  Image image = resizedBilinear(renderer_->readLinear(), full.width, full.height);
  lastMs_ = 1e3 * (steadySeconds() - start);
  return image;
}

void CoarsePreview::invalidate(void (PreviewRenderer::*what)()) {
  if (renderer_) (renderer_.get()->*what)();
}

}  // namespace vplab::ui
