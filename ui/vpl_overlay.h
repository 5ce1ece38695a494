#pragma once
// What the editor's VPL view marks: which VPLs the camera itself sees. A VPL hidden behind a wall is drawn as a
// hollow ring, so that VPLs in another room no longer look as if they sat on the walls in front of them.

#include "renderer/offline/embree_scene.h"
#include "renderer/scene/scene.h"
#include "renderer/vpl/vpl.h"

#include <vector>

namespace vplab::ui {

/// Per VPL: true when it lies in front of the camera and the segment from the camera's position to it is
/// unoccluded (exact visibility, Embree).
std::vector<bool> vplsSeenByCamera(const EmbreeScene& embree, const Camera& camera, const std::vector<Vpl>& vpls);

/// The share of `seen` that is true (0 for none).
double seenShare(const std::vector<bool>& seen);

}  // namespace vplab::ui
