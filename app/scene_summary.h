#pragma once
// The one-line description of a scene that render, preview and reference print: an area light made of two triangles
// is two emissive triangles, not "2 lights".

#include <string>

#include "renderer/scene/scene.h"

namespace vplab::cli {

inline std::string sceneSummary(const Scene& scene) {
  return scene.sourcePath + " (" + std::to_string(scene.triangles.size()) +
         " triangles; lights: " + std::to_string(scene.emissiveTriangles.size()) + " emissive triangles, " +
         std::to_string(scene.punctualLights.size()) + " punctual" +
         (scene.media.empty() ? std::string() : "; media: " + std::to_string(scene.media.size())) + ")";
}

}  // namespace vplab::cli
