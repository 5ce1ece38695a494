#pragma once
// The editor window's panels over an EditorState: they draw it and call its functions, and hold nothing but what only
// the widgets need (text being typed, which sections are open). The view between the panels (ui/view_panel.cpp), the
// controls on the left and the analysis on the right (ui/side_panels.cpp).

#include <string>
#include <vector>

#include "ui/editor_state.h"
#include "ui/media_panel.h"
#include "ui/view_image.h"

namespace vplab::ui {

/// What only the widgets keep between frames.
struct PanelState {
  std::vector<std::string> recent;  ///< recently opened scene files, newest first
  std::string pathInput;
  std::string settingsPath = "vplab-settings.json";
  std::string exportPath = "vplab-view.png";
  std::string ioMessage;  ///< the last file operation's result
  bool showHelp = false;
  bool chartWindowOpen = false;  ///< the chart is shown enlarged in its own window
  MediaPanelInput media;         ///< the media panel's .vdb path, grid name, selection and load error
  bool revealMedia = false;      ///< open the media section on the next frame (a .vdb was dropped)
};

/// Where the view put the image, in window pixels (the window blits the picture there before ImGui draws on top).
struct ViewPlacement {
  float x = 0.0f, y = 0.0f, w = 0.0f, h = 0.0f;
  float scale = 1.0f;  ///< window pixels per image pixel
};

/// Opens `path` in the state and puts it first among the recent files.
void openSceneFromPanel(EditorState& state, PanelState& panels, const std::string& path);
/// A file dropped on the window: a .vdb becomes the smoke of a medium box (openVdb: the selected box, else the first,
/// else a new one) through EditorState::editMedia, and the media section opens to show it or why it failed; any
/// other file opens as a scene.
void openDroppedFile(EditorState& state, PanelState& panels, const std::string& path);

/// The view area: the active preset's explanation above it, the overlays (split divider, VPL dots, notes), the empty
/// state with the render buttons, the status bar. `shown` is what the window displays; `frameMs` the last frame's time.
void drawView(EditorState& state, const ViewImage& shown, double frameMs, ViewPlacement& placed);
/// Scene, camera and lights, media, many-light settings.
void drawLeftPanel(EditorState& state, PanelState& panels);
/// View options, offline pass, chart, presets, files, help.
void drawRightPanel(EditorState& state, PanelState& panels);

}  // namespace vplab::ui
