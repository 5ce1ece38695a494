#include "renderer/offline/emitter_mask.h"

#include "renderer/offline/progressive.h"

namespace vplab {

PixelMask emitterMask(const EmbreeScene& embree, int width, int height, int edge) {
  const Scene& scene = embree.scene();
  constexpr int kRaysPerSide = 4;
  PixelMask mask(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int i = 0; i < kRaysPerSide * kRaysPerSide && !mask.at(x, y); ++i) {
        const float fx = static_cast<float>(x) + (static_cast<float>(i % kRaysPerSide) + 0.5f) / kRaysPerSide;
        const float fy = static_cast<float>(y) + (static_cast<float>(i / kRaysPerSide) + 0.5f) / kRaysPerSide;
        const auto hit =
            embree.intersect(scene.camera.position, cameraRayDirection(scene.camera, fx, fy, width, height));
        if (hit && scene.materials[hit->material].isEmissive()) mask.at(x, y) = 1;
      }
  return dilateMask(mask, edge);
}

}  // namespace vplab
