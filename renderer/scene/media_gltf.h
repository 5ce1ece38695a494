#pragma once
// The glTF extension VPLAB_participating_media (docs/scenes.md): one object on a mesh-less node (a box, or a density
// grid placed by the node) or on a scene (a medium filling all space). The loader hands each object here.

#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "renderer/scene/medium.h"

namespace tinygltf {
class Value;
}

namespace vplab {

inline constexpr const char* kMediaExtension = "VPLAB_participating_media";

/// Reads one extension object into a Medium: sigmaA, sigmaS, g, and the optional
/// "density": {"uri", "grid" = "density", "scale" = 1} read relative to baseDir and placed by worldFromNode (ignored
/// for a medium filling all space, which cannot have a density). Without a density the box is the node's [-1, 1]^3
/// under worldFromNode. Throws SceneError "file: at.field: what" for anything wrong.
Medium readMediumExtension(const tinygltf::Value& ext, bool fillsSpace, const glm::mat4& worldFromNode,
                           const std::string& file, const std::string& baseDir, const std::string& at);

/// Throws SceneError when two media share points (paths: each medium's glTF path, for the message).
void checkMediaDisjoint(const std::vector<Medium>& media, const std::vector<std::string>& paths,
                        const std::string& file);

/// Loads a density grid onto an existing medium (the editor's "open a .vdb"): the grid replaces the medium's box,
/// placed by the box's current centre and axes as if they were a node's transform with the grid's index box centred
/// on it. Throws VdbError (also for a medium that fills all space: it has no box).
void attachDensity(Medium& medium, const std::string& vdbPath, const std::string& gridName, float scale);

}  // namespace vplab
