#pragma once
// Options of the commands that run many renders in one go (bench, stability): the GL backend (or none), the seed,
// the CPU threads, whether per-run images are written, the staging of the scenes, and a log on stderr stamped with the
// seconds since the start.

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "app/cli.h"
#include "app/scene_input.h"
#include "app/settings_options.h"
#include "renderer/gl/context.h"

namespace vplab::cli {

/// Parses --gl auto|egl|osmesa, and "off" when allowOff (then returns false: run without GL).
inline bool parseGlOption(const CommandLine& cl, GlBackend& backend, bool allowOff) {
  std::string name = cl.getString("gl", "auto");
  if (allowOff && name == "off") return false;
  if (!parseGlBackend(name, backend))
    throw CliError("option --gl: '" + name + "' is not " +
                   (allowOff ? "auto, egl, osmesa or off" : "auto, egl or osmesa"));
  return true;
}

/// The settings (table keys) a sweep takes from the settings table as they are: how its scenes are loaded.
inline const std::vector<std::string>& sweepSceneSettings() {
  static const std::vector<std::string> keys = {"stage"};
  return keys;
}

/// The option specs applySweepOptions() reads.
inline std::vector<OptionSpec> sweepOptions(const char* what) {
  std::vector<OptionSpec> options = {
      {"gl", "auto|egl|osmesa|off", std::string("GL context for the preview ") + what + " (default auto; off = CPU only)"},
      {"seed", "S", "seed of every sequence (default 1)"},
      {"threads", "T", "CPU worker threads, 0 = all cores (default 0)"},
      {"no-images", "", "do not write per-run images and heatmaps"}};
  for (OptionSpec& o : settingOptions(Settings{}, sweepSceneSettings())) options.push_back(o);
  return options;
}

/// Fills the members gl, glBackend, seed, threads, writeImages, loadScene and log that BenchConfig and
/// StabilityConfig share. Scenes load as in every other command (app/scene_input.h), staged as --stage says.
template <typename Config>
void applySweepOptions(const CommandLine& cl, const char* label, Config& config) {
  Settings scene;
  applySettingsOptions(cl, scene, sweepSceneSettings());
  config.loadScene = [command = std::string(label), stage = scene.stage](const std::string& path) {
    return loadSceneForCommand(command, path, stage);
  };
  config.gl = parseGlOption(cl, config.glBackend, true);
  int seed = cl.getInt("seed", 1);
  if (seed < 0) throw CliError("option --seed: must be >= 0");
  config.seed = static_cast<uint32_t>(seed);
  config.threads = cl.getInt("threads", 0);
  config.writeImages = !cl.has("no-images");
  auto start = std::chrono::steady_clock::now();
  config.log = [start, label = std::string(label)](const std::string& line) {
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr, "[%s %6.1fs] %s\n", label.c_str(), s, line.c_str());
  };
}

}  // namespace vplab::cli
