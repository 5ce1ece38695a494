#pragma once
// Staging: what a model without lights needs before a many-light method can show anything. A glTF file from a
// modelling tool often holds just the model; rendered as it is, every pass writes a black image. The studio puts the
// model on a ground in front of a backdrop (surfaces for bounce light, which is what VPLs carry), adds one area light
// sized from the model's bounds, and frames the camera on the model. docs/scenes.md shows the result.

#include "renderer/scene/scene.h"
#include "renderer/settings.h"

namespace vplab {

/// Applies `stage` to a loaded scene: Stage::Auto stages only a scene without lights, Stage::Studio always,
/// Stage::None never. Fills Scene::staging with what was added (empty when nothing was) and drops the loader's
/// "no lights" warning once there are lights. Deterministic: the same scene and stage give the same studio.
void stageScene(Scene& scene, Stage stage);

}  // namespace vplab
