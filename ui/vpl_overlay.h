#pragma once
// What the editor's view marks over the image. In the VPL view, which VPLs the camera itself sees: a VPL hidden behind
// a wall is drawn as a hollow ring, so that VPLs in another room no longer look as if they sat on the walls in front
// of them. In every view, the outline of each medium box, so that the bounds of a density grid's smoke (or of fog) can
// be seen and placed.

#include "renderer/offline/embree_scene.h"
#include "renderer/scene/medium.h"
#include "renderer/scene/scene.h"
#include "renderer/vpl/vpl.h"

#include <array>
#include <optional>
#include <vector>

namespace vplab::ui {

/// Where p lands on an image of `aspect` (width / height) seen by `camera`, in normalised device coordinates
/// ([-1, 1]^2 is the image, +y up); nothing when p is not in front of the near plane.
std::optional<glm::vec2> projectToImage(const Camera& camera, float aspect, const glm::vec3& p);

/// A medium box's twelve edges as projectToImage places them, each clipped at the near plane so that a box around the
/// camera still shows the part in front of it; an edge wholly behind it is left out, and a medium filling all space
/// has none.
std::vector<std::array<glm::vec2, 2>> mediumBoxOutline(const Medium& medium, const Camera& camera, float aspect);

/// Per VPL: true when it lies in front of the camera and the segment from the camera's position to it is
/// unoccluded (exact visibility, Embree).
std::vector<bool> vplsSeenByCamera(const EmbreeScene& embree, const Camera& camera, const std::vector<Vpl>& vpls);

/// The share of `seen` that is true (0 for none).
double seenShare(const std::vector<bool>& seen);

}  // namespace vplab::ui
