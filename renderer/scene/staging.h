#pragma once
// Staging: what a model without lights needs before a many-light method can show anything. A glTF file from a
// modelling tool often holds just the model; rendered as it is, every pass writes a black image. The studio puts the
// model on a ground in front of a backdrop (surfaces for bounce light, which is what VPLs carry), adds one area light
// sized from the model's bounds, and frames the camera on the model. docs/scenes.md shows the result.

#include "renderer/scene/scene.h"
#include "renderer/settings.h"

#include <cstdint>
#include <string>

namespace vplab {

/// Applies `stage` to a loaded scene: Stage::Auto stages only a scene without lights, Stage::Studio always,
/// Stage::None never. Fills Scene::staging with what was added (empty when nothing was) and drops the loader's
/// "no lights" warning once there are lights. Deterministic: the same scene and stage give the same studio.
void stageScene(Scene& scene, Stage stage);

/// Appends a one-sided square area light (two triangles, a material of its own named `name`) of side `side`
/// centred at `center` and facing `target`, with the radiance that gives a surface at `target` facing it the
/// irradiance `irradiance` (lux). Returns the new material's index. The caller calls Scene::finalize().
uint32_t addSquareLight(Scene& scene, const glm::vec3& center, const glm::vec3& target, float side, float irradiance,
                        const std::string& name);

}  // namespace vplab
