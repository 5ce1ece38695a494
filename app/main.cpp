// vplab: command-line entry. Thin: every subcommand is a function in app/cmd_*.cpp over the renderer library.

#include "app/cli.h"
#include "app/commands.h"
#include "renderer/core/atomic_file.h"
#include "renderer/core/text.h"
#include "renderer/image/image_io.h"
#include "renderer/offline/render_methods.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/lights_json.h"
#include "renderer/settings_json.h"

#include <csignal>
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

namespace {

// The exit statuses, one per kind of outcome.
constexpr int kExitSuccess = 0;
constexpr int kExitCheckFailed = 1;  // returned by compare, stability and the editor's expectations
constexpr int kExitUsage = 2;
constexpr int kExitInput = 3;
constexpr int kExitWrite = 4;
constexpr int kExitMemory = 5;
constexpr int kExitOther = 6;

/// The offline methods' names, comma separated.
std::string methodList() {
  std::string out;
  for (char c : vplab::renderMethodNames(false)) out += c == '|' ? std::string(", ") : std::string(1, c);
  return out;
}

const std::vector<vplab::cli::Command>& commands() {
  static const std::vector<vplab::cli::Command> list = {
      {"edit", "interactive editor: preview, offline pass, split/difference views, chart, presets",
       vplab::app::cmdEdit},
      // The methods from the method table, so that a new row shows here too.
      {"render",
       "exact many-light render (" + methodList() + ") with VPL statistics and metrics against a reference",
       vplab::app::cmdRender},
      {"preview", "headless GL preview (EGL/OSMesa) of the same VPLs: PNG/EXR, per-pass GPU timings",
       vplab::app::cmdPreview},
      {"reference", "path-traced reference image (EXR/PFM/PNG), direct/indirect components",
       vplab::app::cmdReference},
      {"bench", "speed-vs-accuracy sweeps of every method vs a reference: bench.csv, SVG charts, report.md",
       vplab::app::cmdBench},
      {"stability", "flicker under small light/camera motions, failure maps, parameter extremes (exit 1 on bad pixels)",
       vplab::app::cmdStability},
      {"info", "print what a glTF scene contains (counts, lights, materials, camera, warnings)", vplab::app::cmdInfo},
      {"compare", "error metrics of an image against a reference (rmse, relmse, energy ratio), heatmap",
       vplab::app::cmdCompare},
  };
  return list;
}

void printUsage() {
  std::printf("vplab - a rendering lab for many-light (virtual point light) methods\n\n");
  std::printf(
      "usage: vplab <command> [arguments]   (vplab <command> --help for its options; vplab --version)\n\n"
      "commands:\n");
  for (const auto& c : commands()) std::printf("  %-12s %s\n", c.name.c_str(), c.summary.c_str());
  std::printf(
      "\nexit status: %d success; %d a check failed (compare thresholds, stability's bad pixels); %d a usage error\n"
      "(a flag, a settings file or key, an output path refused before any work); %d an input (scene, image,\n"
      "sidecar) that cannot be read or is invalid; %d an output that could not be written; %d out of memory;\n"
      "%d any other failure (no GL context, ...)\n",
      kExitSuccess, kExitCheckFailed, kExitUsage, kExitInput, kExitWrite, kExitMemory, kExitOther);
}

}  // namespace

int main(int argc, char** argv) {
  // Past a file-size limit (ulimit -f) a write must fail with EFBIG and be reported, not kill the process.
  std::signal(SIGXFSZ, SIG_IGN);
  if (argc < 2) {
    printUsage();
    return 2;
  }
  std::string name = argv[1];
  if (name == "--help" || name == "-h" || name == "help") {
    printUsage();
    return 0;
  }
  if (name == "--version" || name == "version") {
    std::printf("vplab %s\n", VPLAB_VERSION);
    return 0;
  }
  std::vector<std::string> args(argv + 2, argv + argc);
  for (const auto& c : commands()) {
    if (c.name != name) continue;
    // One exit status per kind of failure (printed by vplab --help, listed in docs/guide.md), so that a script can
    // tell a mistyped flag from a broken scene from a full disk.
    auto error = [&](int status, const char* what) {
      std::fprintf(stderr, "vplab %s: %s\n", name.c_str(), vplab::printableMessage(what).c_str());
      return status;
    };
    try {
      return c.run(args);
    } catch (const vplab::cli::CliError& e) {
      return error(kExitUsage, e.what());
    } catch (const vplab::SettingsJsonError& e) {
      return error(kExitUsage, e.what());
    } catch (const std::bad_alloc&) {
      const bool sized = name != "info" && name != "compare";
      std::fprintf(stderr, "vplab %s: error: out of memory (%s)\n", name.c_str(),
                   sized ? "try a smaller --size or fewer lights and VPLs" : "the input is too large for this machine");
      return kExitMemory;
    } catch (const vplab::FileWriteError& e) {
      return error(kExitWrite, ("error: " + std::string(e.what())).c_str());
    } catch (const vplab::ImageWriteError& e) {
      return error(kExitWrite, ("error: " + std::string(e.what())).c_str());
    } catch (const vplab::FileReadError& e) {
      return error(kExitInput, ("error: " + std::string(e.what())).c_str());
    } catch (const vplab::SceneError& e) {
      return error(kExitInput, ("error: " + std::string(e.what())).c_str());
    } catch (const vplab::ImageIoError& e) {
      return error(kExitInput, ("error: " + std::string(e.what())).c_str());
    } catch (const vplab::LightsJsonError& e) {
      return error(kExitInput, ("error: " + std::string(e.what())).c_str());
    } catch (const std::exception& e) {
      return error(kExitOther, ("error: " + std::string(e.what())).c_str());
    }
  }
  std::fprintf(stderr, "vplab: unknown command '%s' (see vplab --help)\n", name.c_str());
  return 2;
}
