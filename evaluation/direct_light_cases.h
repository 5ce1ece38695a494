#pragma once
// Scenes that measure the preview's direct light against the reference's (vplab_bench_direct_bench,
// tests/gl_direct_test.cpp): each puts one kind of light where a shadow technique is most likely to go wrong.

#include <string>

#include "renderer/scene/scene.h"

namespace vplab {

/// The Cornell box at `path` with its emitter grown about its centre to side x side metres, the emitted radiance
/// scaled to keep its power: a large light close to the walls and the blocks.
Scene cornellWithLargeEmitter(const std::string& path, float side);
/// The Cornell box at `path` with its emitter replaced by a spot light under the ceiling.
Scene cornellWithSpotLight(const std::string& path);
/// The Cornell box at `path` without its ceiling (nor emitter), under a directional light.
Scene cornellUnderSun(const std::string& path);
/// Adds a point light two bounding radii above the geometry's centre, giving it the irradiance pi (as the editor's
/// "+ point" does).
void addPointLightAbove(Scene& scene);
/// Every material Lambert: no GGX lobe (metallic and specular 0).
void makeLambert(Scene& scene);

}  // namespace vplab
