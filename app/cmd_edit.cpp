// vplab edit [scene]: the interactive ImGui editor, or a scripted run of it (tests, screenshots, benchmarks).

#include "app/cli.h"
#include "app/commands.h"
#include "app/settings_options.h"

#ifdef VPLAB_HAVE_EDITOR
#include "ui/editor.h"
#endif

#include <cstdio>

namespace vplab::app {

int cmdEdit(const Args& args) {
  cli::CommandLine cl("vplab edit [scene.gltf] [options]",
                      {
                          {"script", "s.txt", "run the editor commands in s.txt, then exit (see docs/editor.md)"},
                          {"screenshot", "out.png", "write the whole window as PNG after the script, then exit"},
                          {"window", "WxH", "window size in pixels (default 1280x720)"},
                          {"preview-scale", "S",
                           "preview pixels per view pixel while the preview is fitted to the view, 0.05 to 1 "
                           "(default 0.4; --size turns fitting off)"},
                      });
  const unsigned use = kUseImage | kUseReference | kUseGeneration | kUseCpuVpl | kUseGl;
#ifdef VPLAB_HAVE_EDITOR
  const Settings defaults = previewDefaultSettings();
#else
  const Settings defaults;
#endif
  cl.addOptions(cli::settingOptions(defaults, use));
  if (!cl.parse(args)) {
    std::printf("%s", cl.help().c_str());
    std::printf("Opens the editor on a scene (default: the Cornell box). Needs a display: use xvfb-run without one.\n");
    return 0;
  }
  cl.requirePositional(0, 1, "at most one scene file");
#ifdef VPLAB_HAVE_EDITOR
  ui::EditorOptions options;
  options.scenePath =
      cl.positional().empty() ? std::string(VPLAB_ASSET_DIR) + "/scenes/cornell-box.gltf" : cl.positional()[0];
  options.scriptPath = cl.getString("script", "");
  options.screenshotPath = cl.getString("screenshot", "");
  cl.getSize("window", options.windowWidth, options.windowHeight);
  cli::applySettingsOptions(cl, options.settings, use);
  // An explicit image size (--size, or a settings file with another size) is kept; otherwise the preview is fitted to
  // the view.
  options.fitPreview =
      !cl.has("size") && options.settings.width == Settings{}.width && options.settings.height == Settings{}.height;
  options.previewScale = cl.getFloat("preview-scale", options.previewScale);
  if (!(options.previewScale >= 0.05f && options.previewScale <= 1.0f))
    throw cli::CliError("option --preview-scale: must be in [0.05, 1]");
  return ui::runEditor(options);
#else
  std::fprintf(stderr, "vplab edit: this build has no editor (configured with -DVPLAB_BUILD_EDITOR=OFF)\n");
  return 1;
#endif
}

}  // namespace vplab::app
