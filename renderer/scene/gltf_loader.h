#pragma once
// glTF 2.0 (.gltf and .glb) to Scene: node transforms baked into world space, materials reduced to vplab's
// metallic-roughness model, KHR_lights_punctual lights and the first perspective camera.

#include "renderer/scene/scene.h"

#include <stdexcept>
#include <string>

namespace vplab {

/// A file that cannot be turned into a Scene. The message is one line: the file, then the glTF path of the problem,
/// e.g. `two.gltf: meshes[2].primitives[0].indices: accessor 7 out of range`.
struct SceneError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Largest world-space coordinate accepted (metres). Far inside what Embree accepts (about 1.8e18) and small enough
/// that squared distances and areas stay finite in float.
inline constexpr float kMaxCoordinate = 1e9f;
/// True when every coordinate of v is finite and within +-kMaxCoordinate.
bool withinCoordinateBound(const glm::vec3& v);

/// Largest emitted radiance (cd/m^2), intensity (cd) or irradiance (lx) accepted: the sun's disk is about 1.6e9
/// cd/m^2. With kMaxCoordinate it keeps every light's power finite in float.
inline constexpr double kMaxEmission = 1e15;

/// The warning a scene without lights carries; staging removes it when it adds a light.
inline constexpr const char* kNoLightsWarning = "no lights: the image will be black (--stage studio adds a light)";

/// Loads a glTF 2.0 file (.gltf with external or embedded buffers, or .glb). Every reference and accessor range is
/// validated here; malformed input throws SceneError, never crashes. Non-fatal problems (skipped non-triangle
/// primitives, unloadable textures, no lights) end up in Scene::warnings. The returned scene is finalized.
Scene loadScene(const std::string& path);

}  // namespace vplab
