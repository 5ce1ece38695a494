#pragma once
// Participating media in the editor (docs/theory.md §16): fog boxes and a medium filling all space, added, removed,
// moved and resized, with sigma_a, sigma_s (RGB) and g edited live. The panel and the script's `medium` verb edit a
// copy of the scene's media with the functions below and hand it to EditorState::editMedia, which validates it as
// the loader does (renderer/scene/medium.h, mediaProblem) and marks what the change made stale.

#include <string>
#include <vector>

#include "renderer/scene/medium.h"
#include "renderer/scene/scene.h"

namespace vplab::ui {

/// A grey fog box over the scene's geometry, 1 % inside its bounds (inside a closed room's walls): sigma_a 0.05,
/// sigma_s 0.5 1/m, g 0.3, named "fog N".
Medium newFogBox(const Scene& scene);
/// The same fog filling all space (only valid alone).
Medium newFogEverywhere(const Scene& scene);
/// Moves a box by `offset` (world units), keeping its size and orientation. A medium filling space is unchanged.
void moveMediumBox(Medium& medium, const glm::vec3& offset);
/// Gives a box these half sizes along its own axes, keeping its centre and orientation (values <= 0 make a box
/// without volume, which mediaProblem refuses).
void resizeMediumBox(Medium& medium, const glm::vec3& halfSizes);

/// What the panel shows under a medium's coefficients: the mean free path per channel, and the optical depth across
/// the scene (its geometry's diagonal) and, for a box, along its longest edge; exp(-depth) of the light gets through.
std::string describeMedium(const Medium& medium, float sceneDiagonal);

/// Every medium of `media` with its region (centre and half sizes of a box), sigma_a and sigma_s (RGB) and g, with a
/// remove button, and buttons that add a fog box or fog filling all space; `error` (the last refused edit) in red.
/// Returns true when `media` changed.
bool drawMediaPanel(const Scene& scene, std::vector<Medium>& media, const std::string& error);

}  // namespace vplab::ui
