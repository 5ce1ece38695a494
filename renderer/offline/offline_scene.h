#pragma once
// A scene ready for the CPU passes: the scene, its Embree BVH and its light sampler, built together so that the three
// always describe the same geometry and lights. Every CPU pass (VPL generation, the exact VPL render, the reference)
// takes one of these instead of the three parts.

#include <memory>

#include "renderer/offline/embree_scene.h"
#include "renderer/offline/light_sampler.h"
#include "renderer/scene/scene.h"

namespace vplab {

class OfflineScene {
 public:
  /// Builds the BVH and light sampler of a scene the caller keeps alive (and may re-aim: the camera is read at each
  /// pass, the geometry and lights only here).
  explicit OfflineScene(const Scene& scene);
  /// Takes the scene over, so a moved light is a new OfflineScene.
  explicit OfflineScene(Scene&& scene);
  OfflineScene(const OfflineScene&) = delete;
  OfflineScene& operator=(const OfflineScene&) = delete;

  const Scene& scene() const { return *scene_; }
  const EmbreeScene& embree() const { return *embree_; }
  const LightSampler& lights() const { return *lights_; }
  /// The scene's punctual lights were edited in place (moved, rescaled, added): rebuilds the light sampler only. The
  /// BVH is kept, which is right as long as no triangle moved (an emissive triangle is geometry: rebuild instead).
  void punctualLightsChanged() { lights_ = std::make_unique<LightSampler>(*scene_); }

 private:
  std::unique_ptr<Scene> owned_;
  const Scene* scene_;
  std::unique_ptr<EmbreeScene> embree_;
  std::unique_ptr<LightSampler> lights_;
};

}  // namespace vplab
