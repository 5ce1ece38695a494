#pragma once
// Teaching presets: one click sets up a classic many-light artifact, or its remedy, on one of the bundled scenes
// (docs/scenes.md), with a few sentences on what to look at and why it happens (docs/theory.md §9).

#include "renderer/settings.h"
#include "ui/view_mode.h"

#include <string>
#include <vector>

namespace vplab::ui {

struct TeachingPreset {
  std::string name;
  std::string scene;  ///< file name under assets/scenes/
  Settings settings;  ///< complete settings (defaults plus the preset's changes)
  ViewMode view = ViewMode::Preview;
  bool animateLight = false;     ///< moves the first light on a small circle every frame
  bool reseedEveryFrame = false;  ///< draws a new VPL seed every frame (the flicker demonstration)
  std::string explanation;        ///< what to look at and why it happens
};

/// The presets in teaching order: each artifact followed by its remedy.
const std::vector<TeachingPreset>& teachingPresets();

}  // namespace vplab::ui
