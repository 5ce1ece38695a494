#pragma once
// Participating media in the editor (docs/theory.md §16, §22): fog boxes and a medium filling all space, added,
// removed, moved and resized, with sigma_a, sigma_s (RGB) and g edited live; a box may carry a density grid (smoke)
// opened from a .vdb file, with its density scale edited live. The panel, a .vdb dropped on the window and the
// script's `medium` verb edit a copy of the scene's media with the functions below and hand it to
// EditorState::editMedia, which validates it as the loader does (renderer/scene/medium.h, mediaProblem) and marks
// what the change made stale.

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
/// For a density grid the figures are those of its densest voxel (sigmaTMax): the shortest free path ("down to") and
/// the largest depths ("up to").
std::string describeMedium(const Medium& medium, float sceneDiagonal);

/// The grid a .vdb is read for when none is named: OpenVDB's usual name for smoke, and the scene format's default.
inline constexpr const char* kDefaultDensityGrid = "density";

/// What only the media panel's widgets keep between frames.
struct MediaPanelInput {
  std::string vdbPath;                         ///< the .vdb file being typed
  std::string gridName = kDefaultDensityGrid;  ///< the grid read from it
  int selected = -1;                           ///< the medium last clicked in the panel (-1: none)
  std::string vdbError;                        ///< why the last .vdb could not be opened (empty after one that could)
};

/// Which medium a .vdb opened in the panel or dropped on the window goes to: the selected medium when it is a box,
/// else the first box, else -1 (a new fog box is made for it). A medium filling all space has no box to hold a grid.
int densityTarget(const std::vector<Medium>& media, int selected);

/// Loads grid `gridName` of the .vdb at `path` onto media[index] (attachDensity: the grid fitted into the box, the
/// medium's density scale kept), or onto a new fog box appended when index is -1. Returns the medium's index. Throws
/// VdbError (an unreadable file, no such grid, ...) with `media` left as it was; index must name a box.
std::size_t attachVdb(const Scene& scene, std::vector<Medium>& media, int index, const std::string& path,
                      const std::string& gridName);

/// The panel's "open .vdb" and a dropped .vdb: attachVdb of `path` onto densityTarget(media, input.selected) with
/// input's grid name. The medium it went to becomes the selected one; a file that cannot be read leaves `media` as it
/// was and its message in input.vdbError. Returns whether `media` changed.
bool openVdb(const Scene& scene, std::vector<Medium>& media, MediaPanelInput& input, const std::string& path);

/// Every medium of `media` with its region (centre and half sizes of a box), sigma_a and sigma_s (RGB) and g, for a
/// density grid its file, grid, voxels and density range with a density scale, a remove button; buttons that add a
/// fog box or fog filling all space, and a .vdb path with the grid's name that openVdb loads; `error` (the last
/// refused edit) and input.vdbError in red. Clicking a medium's name selects it. Returns true when `media` changed.
bool drawMediaPanel(const Scene& scene, std::vector<Medium>& media, const std::string& error, MediaPanelInput& input);

}  // namespace vplab::ui
