#pragma once
// A scene's lights and media as a small JSON sidecar file, so that lights added, moved, aimed, scaled or deleted in
// the editor (the studio light of a staged scene included), and media added, removed, moved, resized or with new
// coefficients, come back when the scene is opened again, in the editor and in the rendering commands alike. The
// sidecar of `model.glb` is `model.glb.lights.json`.

#include "renderer/scene/scene.h"

#include <stdexcept>
#include <string>

namespace vplab {

/// A lights file that cannot be read or applied. The message names the file and the key.
struct LightsJsonError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// `scenePath` + ".lights.json".
std::string lightsSidecarPath(const std::string& scenePath);

/// Every punctual light, every area light as its emissive material's name and radiance with its triangles (and
/// their texture coordinates when the material has a texture, so that an emissive texture keeps its place), and every
/// medium (name, sigmaA, sigmaS, g, and fillsSpace or its box's worldFromBox, column-major; a density grid as its
/// file, grid name and scale, the file relative to the sidecar unless absolute).
std::string lightsToJson(const Scene& scene);
/// Writes lightsToJson() through a temporary file renamed into place, so a failed write leaves no partial file.
void saveLightsFile(const std::string& path, const Scene& scene);
/// Replaces the scene's lights with the file's: the punctual lights as listed; the scene's emissive triangles are
/// removed and the file's area lights added (reusing a material of the same name, with the file's radiance). The
/// scene is finalized. A file with "media" replaces the scene's media (checked as the loader checks them: finite
/// coefficients in range, |g| < 1, boxes with volume that do not overlap); one without keeps them. On any error
/// (LightsJsonError naming the file and key) the scene is left unchanged.
void applyLightsFile(const std::string& path, Scene& scene);

/// Applies lightsSidecarPath(scene.sourcePath) when that file exists, and notes it in Scene::staging. Returns
/// whether it did. Called after staging, so saved lights replace the studio's light too.
bool applyLightsSidecar(Scene& scene);

}  // namespace vplab
