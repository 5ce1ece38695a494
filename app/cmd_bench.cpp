// vplab bench <scene>...: speed-versus-accuracy sweeps of every many-light method against a cached reference;
// bench.csv, SVG charts and report.md in the output folder.

#include <chrono>
#include <cstdio>
#include <sstream>

#include "app/cli.h"
#include "app/commands.h"
#include "app/file_plan.h"
#include "app/sweep_options.h"
#include "evaluation/sweep.h"
#include "renderer/gl/context.h"

namespace vplab::app {

int cmdBench(const Args& args) {
  cli::CommandLine cl(
      "vplab bench <scene.gltf>... [--out dir] [--size WxH] [--quick] [--methods list] [--ref-spp N]",
      {{"out", "DIR", "output folder: bench.csv, charts/, images/, references/, report.md (default bench-out)"},
       {"size", "WxH", "image size (default 128x128)"},
       {"quick", "", "fewer parameter values and VPLs (a minute per scene instead of several)"},
       {"methods", "LIST", "comma-separated subset of vpl,clamp,ssbc,vsl,reject,vpl-kk (default all)"},
       {"ref-spp", "N", "reference samples per pixel (default 1024, 256 with --quick)"},
       {"samples-per-pixel", "N", "samples per pixel of the CPU VPL renders (default 4, 2 with --quick)"},
       {"components", "indirect|all", "what is compared with the reference (default indirect)"}});
  cl.addOptions(cli::sweepOptions("variants"));
  if (!cl.parse(args)) {
    std::printf("%s", cl.help().c_str());
    std::printf(
        "Re-running with the same --out reuses the cached reference and skips the runs already in bench.csv;\n"
        "an interrupted sweep keeps every row measured so far.\n");
    return 0;
  }
  cl.requirePositional(1, 64, "one or more scene files");
  BenchConfig config;
  config.outDir = cl.getString("out", "bench-out");
  config.quick = cl.has("quick");
  config.referenceSpp = config.quick ? 256 : 1024;
  config.cpuSpp = config.quick ? 2 : 4;
  cl.getSize("size", config.width, config.height);
  config.referenceSpp = cl.getInt("ref-spp", config.referenceSpp);
  config.cpuSpp = cl.getInt("samples-per-pixel", config.cpuSpp);
  if (config.referenceSpp < 1 || config.cpuSpp < 1)
    throw cli::CliError("--ref-spp and --samples-per-pixel must be >= 1");
  if (config.width < 1 || config.height < 1 || config.width > 4096 || config.height > 4096)
    throw cli::CliError("option --size: each side must be in [1, 4096]");
  if (auto m = cl.value("methods")) {
    std::stringstream ss(*m);
    std::string name;
    while (std::getline(ss, name, ',')) {
      if (name.empty()) continue;
      const auto& known = benchMethodNames();
      if (std::find(known.begin(), known.end(), name) == known.end())
        throw cli::CliError("option --methods: unknown method '" + name + "' (vpl, clamp, ssbc, vsl, reject, vpl-kk)");
      config.methods.push_back(name);
    }
  }
  std::string comp = cl.getString("components", "indirect");
  if (comp == "indirect")
    config.components = Components::Indirect;
  else if (comp == "all")
    config.components = Components::All;
  else
    throw cli::CliError("option --components: '" + comp + "' is not indirect or all");
  cli::applySweepOptions(cl, "bench", config);
  cli::requireOutputFolder(config.outDir, cl.positional());

  BenchOutcome out = runBench(cl.positional(), config);
  std::printf("runs        %zu measured, %zu reused from %s\n", out.rowsMeasured, out.rowsReused, out.csvPath.c_str());
  if (!out.glNote.empty()) std::printf("note        %s\n", out.glNote.c_str());
  for (const std::string& c : out.charts) std::printf("chart       %s\n", c.c_str());
  std::printf("report      %s\n", out.reportPath.c_str());
  return 0;
}

}  // namespace vplab::app
