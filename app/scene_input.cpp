#include "app/scene_input.h"

#include <cstdio>

#include "renderer/core/text.h"
#include "renderer/offline/light_sampler.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/lights_json.h"
#include "renderer/scene/staging.h"

namespace vplab::cli {

Scene loadSceneForCommand(const std::string& command, const std::string& path, Stage stage) {
  Scene scene = loadScene(path);
  stageScene(scene, stage);
  applyLightsSidecar(scene);
  for (const std::string& w : scene.warnings)
    std::fprintf(stderr, "vplab %s: warning: %s\n", command.c_str(), printable(w).c_str());
  if (!scene.staging.empty())
    std::fprintf(stderr, "vplab %s: staged %s\n", command.c_str(), printable(scene.staging).c_str());
  // Lights that exist but emit nothing (zero intensity): the loader's "no lights" warning does not cover them.
  if (scene.hasLights() && LightSampler(scene).empty())
    std::fprintf(stderr, "vplab %s: %s: every light has zero power: the image is black\n", command.c_str(),
                 printable(scene.sourcePath).c_str());
  return scene;
}

}  // namespace vplab::cli
