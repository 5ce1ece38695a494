#include "renderer/offline/offline_scene.h"

namespace vplab {

OfflineScene::OfflineScene(const Scene& scene)
    : scene_(&scene), embree_(std::make_unique<EmbreeScene>(scene)), lights_(std::make_unique<LightSampler>(scene)) {}

OfflineScene::OfflineScene(Scene&& scene)
    : owned_(std::make_unique<Scene>(std::move(scene))),
      scene_(owned_.get()),
      embree_(std::make_unique<EmbreeScene>(*scene_)),
      lights_(std::make_unique<LightSampler>(*scene_)) {}

}  // namespace vplab
