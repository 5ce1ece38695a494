#pragma once
// The scene a rendering subcommand works on: loaded, staged as Settings::stage says, its warnings and staging
// reported once on stderr.

#include "renderer/scene/scene.h"
#include "renderer/settings.h"

#include <string>

namespace vplab::cli {

/// loadScene() then stageScene(); prints "vplab <command>: warning: ..." for each load warning, "vplab <command>:
/// staged ..." when staging added something, and one line when the lights emit nothing. SceneError propagates.
Scene loadSceneForCommand(const std::string& command, const std::string& path, Stage stage);

}  // namespace vplab::cli
