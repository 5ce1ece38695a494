#pragma once
// The scene a rendering subcommand works on: loaded, staged as Settings::stage says, with the lights saved next to it
// by the editor, its warnings and staging reported once on stderr.

#include "renderer/scene/scene.h"
#include "renderer/settings.h"

#include <string>

namespace vplab::cli {

/// loadScene(), stageScene(), then the lights sidecar saved by the editor when there is one (lights_json.h); prints "vplab <command>: warning: ..." for each load warning, "vplab <command>:
/// staged ..." when staging added something, and one line when the lights emit nothing. SceneError propagates.
Scene loadSceneForCommand(const std::string& command, const std::string& path, Stage stage);

}  // namespace vplab::cli
