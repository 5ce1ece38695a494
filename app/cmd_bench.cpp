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
      "vplab bench <scene.gltf>... [--out dir] [--size WxH] [--quick] [--methods list] [--ref-spp N] [--shard i/n]\n"
      "       vplab bench --merge <shard dir>... [--out dir]",
      {{"out", "DIR", "output folder: bench.csv, charts/, images/, references/, report.md (default bench-out)"},
       {"size", "WxH", "image size (default 128x128)"},
       {"quick", "", "fewer parameter values and VPLs (a minute per scene instead of several)"},
       {"methods", "LIST", "comma-separated subset of " + cli::joined(benchMethodNames()) + " (default all)"},
       {"ref-spp", "N", "reference samples per pixel (default 1024, 256 with --quick)"},
       {"exact-samples-per-pixel", "N", "samples per pixel of the exact CPU VPL renders (default 4, 2 with --quick)"},
       {"components", "indirect|all", "what is compared with the reference (default indirect)"},
       {"shard", "i/n", "run only part i of n of the sweep (1 <= i <= n): runs k with k mod n = i - 1"},
       {"merge", "", "the arguments are shard folders: join their bench.csv into --out and write its report"}});
  cl.addOptions(cli::sweepOptions("variants"));
  if (!cl.parse(args)) {
    std::printf("%s", cl.help().c_str());
    std::printf(
        "Re-running with the same --out reuses the cached reference and skips the runs already in bench.csv;\n"
        "an interrupted sweep keeps every row measured so far. Shards (--shard) of one sweep run on any machines\n"
        "with the same arguments; --merge joins their folders (docs/guide.md has GNU parallel and Slurm recipes).\n");
    return 0;
  }
  BenchConfig config;
  config.outDir = cl.getString("out", "bench-out");
  if (cl.has("merge")) {
    cl.requirePositional(1, 100000, "one or more shard folders");
    if (cl.has("shard")) throw cli::CliError("--merge joins shards; it takes no --shard");
    cli::requireOutputFolder(config.outDir, {});
    BenchOutcome out = mergeBench(cl.positional(), config);
    std::printf("runs        %zu merged, %zu already in %s\n", out.rowsMeasured, out.rowsReused, out.csvPath.c_str());
    for (const std::string& c : out.charts) std::printf("chart       %s\n", c.c_str());
    std::printf("report      %s\n", out.reportPath.c_str());
    return 0;
  }
  cl.requirePositional(1, 64, "one or more scene files");
  if (auto shard = cl.value("shard")) {
    int i = 0, n = 0;
    char rest = 0;
    if (std::sscanf(shard->c_str(), "%d/%d%c", &i, &n, &rest) != 2 || n < 1 || n > 100000 || i < 1 || i > n)
      throw cli::CliError("option --shard: '" + *shard + "' is not i/n with 1 <= i <= n (for example 2/8)");
    config.shardIndex = i - 1;
    config.shardCount = n;
  }
  config.quick = cl.has("quick");
  config.referenceSpp = config.quick ? 256 : 1024;
  config.cpuSpp = config.quick ? 2 : 4;
  cl.getSize("size", config.width, config.height);
  config.referenceSpp = cl.getInt("ref-spp", config.referenceSpp);
  config.cpuSpp = cl.getInt("exact-samples-per-pixel", config.cpuSpp);
  if (config.referenceSpp < 1 || config.cpuSpp < 1)
    throw cli::CliError("--ref-spp and --exact-samples-per-pixel must be >= 1");
  if (config.width < 1 || config.height < 1 || config.width > 4096 || config.height > 4096)
    throw cli::CliError("option --size: each side must be in [1, 4096]");
  if (auto m = cl.value("methods")) {
    std::stringstream ss(*m);
    std::string name;
    while (std::getline(ss, name, ',')) {
      if (name.empty()) continue;
      const auto& known = benchMethodNames();
      if (std::find(known.begin(), known.end(), name) == known.end())
        throw cli::CliError("option --methods: unknown method '" + name + "' (" + cli::joined(known) + ")");
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
  if (config.shardCount > 1) {
    if (!out.glNote.empty()) std::printf("note        %s\n", out.glNote.c_str());
    std::printf("shard       %d/%d: join the shard folders with vplab bench --merge\n", config.shardIndex + 1,
                config.shardCount);
    return 0;
  }
  if (!out.glNote.empty()) std::printf("note        %s\n", out.glNote.c_str());
  for (const std::string& c : out.charts) std::printf("chart       %s\n", c.c_str());
  std::printf("report      %s\n", out.reportPath.c_str());
  return 0;
}

}  // namespace vplab::app
