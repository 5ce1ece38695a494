// vplab: command-line entry. Thin: every subcommand is a function in app/cmd_*.cpp over the renderer library.

#include "app/cli.h"
#include "app/commands.h"

#include <csignal>
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

namespace {

const std::vector<vplab::cli::Command>& commands() {
  static const std::vector<vplab::cli::Command> list = {
      {"edit", "interactive editor: preview, offline pass, split/difference views, chart, presets",
       vplab::app::cmdEdit},
      {"render", "exact VPL render (vpl, vpl-kk, vsl) with VPL statistics and metrics against a reference",
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
    try {
      return c.run(args);
    } catch (const vplab::cli::CliError& e) {
      std::fprintf(stderr, "vplab %s: %s\n", name.c_str(), e.what());
      return 2;
    } catch (const std::bad_alloc&) {
      std::fprintf(stderr, "vplab %s: error: out of memory (try a smaller --size or fewer VPLs)\n", name.c_str());
      return 1;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "vplab %s: error: %s\n", name.c_str(), e.what());
      return 1;
    }
  }
  std::fprintf(stderr, "vplab: unknown command '%s' (see vplab --help)\n", name.c_str());
  return 2;
}
