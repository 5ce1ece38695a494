#pragma once
// One function per subcommand; each parses its own arguments (without the program and command names) and returns
// the process exit status: 0 success, 1 runtime failure (bad file, ...), 2 usage error.

#include <string>
#include <vector>

namespace vplab::app {

using Args = std::vector<std::string>;

/// vplab info <scene>: counts, bounds, lights, materials, camera and load warnings.
int cmdInfo(const Args& args);
/// vplab compare: error metrics (and a heatmap) of an image against a reference.
int cmdCompare(const Args& args);
/// vplab reference <scene>: the path-traced reference image.
int cmdReference(const Args& args);
/// vplab render <scene> --method vpl|vpl-kk|vsl: VPL generation and the exact VPL render.
int cmdRender(const Args& args);
/// vplab preview <scene>: the headless GL preview (EGL/OSMesa) of the same VPLs, with per-pass timings.
int cmdPreview(const Args& args);

/// vplab bench <scene>...: speed-vs-accuracy sweeps of every method against a cached reference, CSV + SVG charts.
int cmdBench(const Args& args);
/// vplab stability <scene>: flicker under small motions, failure maps and the grid of parameter extremes.
int cmdStability(const Args& args);

/// vplab edit [scene]: the interactive editor (or a scripted run of it).
int cmdEdit(const Args& args);

}  // namespace vplab::app
