#pragma once
// Teaching presets: one click sets up a classic many-light artifact, or its remedy, on one of the bundled scenes
// (docs/scenes.md), with a few sentences on what to look at and why it happens (docs/theory.md §9). Every preset is
// complete: its settings start from presetBaseline() and the editor reloads its scene (lights as in the file, the
// scene camera) and resets the view options, so applying it after any other preset gives the same image as applying
// it first.

#include "renderer/settings.h"
#include "ui/view_mode.h"

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace vplab::ui {

/// The offline render a preset starts, because its point is a comparison with it.
enum class PresetOffline {
  None,
  Reference,  ///< the path-traced reference
  ExactVpl,   ///< the exact CPU render of the same VPLs (exactCounterpartOf)
  Chosen,     ///< TeachingPreset::offlineMethod (a media method: vpl-abc, vrl, vbl)
};

struct TeachingPreset {
  std::string name;
  std::string scene;  ///< file name under assets/scenes/
  Settings settings;  ///< complete settings: presetBaseline() plus the preset's changes
  ViewMode view = ViewMode::Preview;
  bool signedDifference = false;  ///< the difference view shows preview - offline instead of the relative error
  bool showRejected = false;      ///< the VPL view also marks the candidates rejection dropped
  PresetOffline offline = PresetOffline::None;
  /// The offline panel's method choice the preset sets; rendered at once when offline is Chosen.
  Method offlineMethod = Method::Vrl;
  bool animateLight = false;      ///< moves the first light on a small circle every frame
  bool reseedEveryFrame = false;  ///< draws a new VPL seed every frame (the flicker demonstration)
  float divider = 0.5f;           ///< split view: share of the image left of the divider (across what it compares)
  std::string explanation;        ///< what to look at and why it happens
};

/// The settings every preset starts from: the defaults with a 256 x 256 image (interactive on software GL).
Settings presetBaseline();

/// The presets in teaching order: each artifact followed by its remedy.
const std::vector<TeachingPreset>& teachingPresets();

/// The preset of that name, or nullptr.
const TeachingPreset* findPreset(const std::string& name);

/// "no preset named 'x'; the presets are:" followed by every name on a line of its own.
std::string unknownPresetMessage(const std::string& name);

/// What the editor shows with an active preset: its name, what it started, the explanation.
std::string presetDescription(const TeachingPreset& preset);

/// The light animation's offset for one frame: the first light moves on a horizontal circle of 2 % of the scene
/// diagonal, one turn every kLightAnimationFrames frames; `phase` (radians) advances by one frame's step.
inline constexpr int kLightAnimationFrames = 120;
glm::vec3 lightAnimationStep(float& phase, float sceneDiagonal);

}  // namespace vplab::ui
