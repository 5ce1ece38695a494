// vplab stability <scene>: flicker under small light and camera motions (coherent vs reshuffled VPLs), failure maps
// per method and the grid of parameter extremes. Exits with status 1 when an extreme produces a bad pixel.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <sstream>

#include "app/cli.h"
#include "app/commands.h"
#include "app/file_plan.h"
#include "app/sweep_options.h"
#include "evaluation/stability.h"
#include "renderer/gl/context.h"

namespace vplab::app {

int cmdStability(const Args& args) {
  cli::CommandLine cl("vplab stability <scene.gltf> [--out dir] [--frames F] [--quick]",
                      {{"out", "DIR",
                        "output folder: flicker/failures/extremes CSV, charts/, images/, stability.md "
                        "(default stability-out)"},
                       {"frames", "F", "frames of each scripted motion, >= 2 (default 8, 4 with --quick)"},
                       {"quick", "", "fewer methods, VPLs and samples"},
                       {"size", "WxH", "image size (default 96x96, 64x64 with --quick)"},
                       {"vpl-count", "N", "VPLs of every method (default 256, 64 with --quick)"},
                       {"ref-spp", "N", "samples per pixel of the reference frames (default 256, 64 with --quick)"},
                       {"methods", "LIST", "flicker methods: " + cli::joined(flickerMethodNames())}});
  cl.addOptions(cli::sweepOptions("parts"));
  if (!cl.parse(args)) {
    std::printf("%s", cl.help().c_str());
    return 0;
  }
  cl.requirePositional(1, 1, "one scene file");
  StabilityConfig config;
  config.outDir = cl.getString("out", "stability-out");
  config.quick = cl.has("quick");
  if (config.quick) {
    config.frames = 4;
    config.width = config.height = 64;
    config.vplCount = 64;
    config.referenceSpp = 64;
  }
  config.frames = cl.getInt("frames", config.frames);
  if (config.frames < 2) throw cli::CliError("option --frames: at least 2 frames are needed");
  cl.getSize("size", config.width, config.height);
  config.vplCount = cl.getInt("vpl-count", config.vplCount);
  config.referenceSpp = cl.getInt("ref-spp", config.referenceSpp);
  if (config.vplCount < 1 || config.referenceSpp < 1) throw cli::CliError("--vpl-count and --ref-spp must be >= 1");
  if (auto m = cl.value("methods")) {
    std::stringstream ss(*m);
    std::string name;
    while (std::getline(ss, name, ','))
      if (!name.empty()) config.flickerMethods.push_back(name);
    const std::vector<std::string>& known = flickerMethodNames();
    for (const std::string& n : config.flickerMethods)
      if (std::find(known.begin(), known.end(), n) == known.end())
        throw cli::CliError("option --methods: unknown flicker method '" + n + "' (" + cli::joined(known) + ")");
  }
  cli::applySweepOptions(cl, "stability", config);
  cli::requireOutputFolder(config.outDir, cl.positional());

  StabilityOutcome out = runStability(cl.positional()[0], config);
  for (const FlickerRow& r : out.flicker)
    if (r.method != "reference")
      std::printf("flicker     %-6s %-8s %-10s %.4g (reference %.4g, excess %.4g)\n", r.motion.c_str(),
                  r.method.c_str(), r.vplMode.c_str(), r.flicker, r.referenceFlicker, r.excess);
  std::size_t bad = 0;
  for (const ExtremeRow& r : out.extremes)
    if (r.bad.total() > 0) {
      ++bad;
      std::printf("BAD         %s = %s, %s (%s): %zu non-finite, %zu negative pixels\n", r.parameter.c_str(),
                  r.value.c_str(), r.method.c_str(), toString(r.backend), r.bad.nonFinite, r.bad.negative);
    }
  std::printf("extremes    %zu run, %zu with bad pixels\n", out.extremes.size(), bad);
  if (!out.glNote.empty()) std::printf("note        %s\n", out.glNote.c_str());
  std::printf("report      %s\n", out.reportPath.c_str());
  return out.extremesClean ? 0 : 1;
}

}  // namespace vplab::app
