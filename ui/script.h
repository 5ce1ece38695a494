#pragma once
// Editor scripts: a text file of commands that drives `vplab edit` without a user (tests, screenshots, benchmarks).
// One command per line, '#' starts a comment. Parsing checks every verb and argument count up front, so a typo
// fails before the window opens, with the line number.
//
//   set <setting> <value>          a Settings member by its JSON key (settings_json.h), e.g. set clampBound 0.5
//   orbit <dx> <dy>                orbit the camera by degrees of yaw and pitch
//   pan <dx> <dy>                  pan by fractions of the distance to the orbit target
//   zoom <steps>                   zoom by 0.9^steps of the distance
//   reset-camera                   back to the scene camera
//   light <index> move <dx> <dy> <dz>      move a punctual light (scene units)
//   light <index> intensity <scale>        scale a punctual light's intensity
//   medium add box|space           add a grey fog box over the geometry, or fog filling all space (ui/media_panel.h)
//   medium <i> remove              remove medium i
//   medium <i> sigmaA|sigmaS <r> <g> <b>   set an absorption or scattering coefficient (1/m, per channel)
//   medium <i> g <value>           set the Henyey-Greenstein asymmetry
//   medium <i> move <dx> <dy> <dz> move a box; medium <i> size <hx> <hy> <hz> gives it these half sizes
//   medium <i> vdb <path> [grid]   load a .vdb file's grid (default "density") into box i as its smoke (media_panel.h,
//                                  attachVdb); a file that cannot give one fails with its message
//   medium <i> density <scale>     set a density grid's scale (>= 0)
//                                  (an edit the loader would refuse fails with its message)
//   save-sidecar                   write the scene's lights and media next to the scene file (lights_json.h)
//   view <mode>                    preview | reference | split | difference | ssbc-residual | vpls
//   preset <name>                  a teaching preset by its name (the rest of the line; an unknown name fails at
//                                  parse time, listing the presets); prints the preset's description
//   frames <n>                     render n frames (the UI needs >= 2 before a screenshot)
//   screenshot <path.png>          the whole window as PNG
//   save-view <path>               the linear image of the preview (.exr, .pfm or .png)
//   offline <reference|vpl|method> start the offline pass with the current settings and camera: the path-traced
//                                  reference, the exact counterpart of the preview, or a method of the render-method
//                                  table (vpl-kk, vsl, vpl-abc, vrl, vbl)
//   wait-offline                   render frames until the offline pass is done
//   load-settings <f.json>         apply a settings file
//   save-settings <f.json>         write the current settings
//   mark                           remember the work counters
//   expect-no-vpl-regeneration     fail unless no VPL generation ran since the mark
//   expect-no-shadow-map-render    fail unless no VPL shadow map was rendered since the mark
//   expect-vpl-regeneration        fail unless VPLs were generated since the mark
//   counters                       print the work counters on stdout
//   time-frames <n> [light|medium <i>]  render n frames while the camera orbits (or light i is dragged, or medium i's
//                                  sigmaS is dragged) and print the mean, median, p95 and largest frame time, the
//                                  UI's share and the updates finished
//   preview-scale <s>              fit the preview to the view at s preview pixels per window pixel (0.05 to 1)
//   change-cost                    print what the last change cost: ms from the change to the final image, frames
//   preset-state                   print a fingerprint of everything a preset sets (settings, scene file, lights,
//                                  camera, view options, animation): equal after any predecessor

#include <stdexcept>
#include <string>
#include <vector>

namespace vplab::ui {

class EditorState;

struct ScriptError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct ScriptCommand {
  int line = 0;  ///< 1-based line in the script
  std::string verb;
  std::vector<std::string> args;
};

/// Parses a whole script; `source` names it in messages ("s.txt:3: ..."). Throws ScriptError.
std::vector<ScriptCommand> parseScript(const std::string& text, const std::string& source);
/// Reads and parses a script file. Throws ScriptError naming the file.
std::vector<ScriptCommand> loadScript(const std::string& path);

/// Runs a command on the editor's state through the functions the panels call. Returns false for the verbs that need
/// the window's frame loop (frames, screenshot, wait-offline, time-frames). Throws ScriptError naming the line.
bool runStateCommand(EditorState& state, const ScriptCommand& command, const std::string& source);

/// Numeric argument i of a command, with the command's location in the message when it is not a number.
double scriptNumber(const ScriptCommand& command, std::size_t i, const std::string& source);

}  // namespace vplab::ui
