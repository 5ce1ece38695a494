// Preview at scale: what a change costs on scenes of 10k, 100k and 1M triangles (scripts/make_dense_scene.py) or any
// glTF file, with each VPL visibility technique (cube maps, imperfect shadow maps). Per scene and technique, at
// 640x480, 256 VPLs, k = 4, 2 SSBC steps, b = 20 (the target configuration of docs/benchmarks.md):
//   load       glTF load + BVH + light sampler (CPU)
//   first      the first preview (scene upload, ISM points, every map, shader compiles)
//   vpl change a new VPL set (the maximum VPL bounce changed, so positions move and the direct light stays):
//              generation + VPL maps + gather + SSBC, wall time and process CPU time, with its parts
//   light move every punctual light moved 2 cm: light sampler, VPL generation, the lights' maps and the VPL maps,
//              direct light, gather, SSBC, wall time and process CPU time, with its parts (scenes whose only
//              lights are emissive triangles move geometry, which rebuilds the scene: not measured here)
//   reference  the Embree reference at 256x256, 16 spp, BVH included (the yardstick: a preview slower than this is
//              not interactive)
// Changes are timed as the median of --repeats after a warm-up. Prints a table, writes a CSV.
//
// Any glTF file works: each scene is staged as the commands stage it (--stage, default auto: a studio with an area
// light around a model without lights) and gets its lights sidecar (model.glb.lights.json) when there is one;
// --point-light adds a point light above the model (the editor's "+ point": irradiance pi at the model's centre), so
// that a third-party model measures the light move too.
//
// --ism-point-budget P and --ism-tile-size T set the ISM parameters (defaults: the Settings defaults), for the sweep of
// scripts/ism_sweep.sh. --indirect-downscale 1,2 (the default) measures each technique with the indirect light and its
// compensation per pixel and on the half-resolution grid (Settings::indirectDownscale), a row each.
//
// usage: vplab_bench_scale_bench [--gl auto|egl|osmesa] [--visibility cube,ism] [--indirect-downscale 1,2]
//                                [--repeats R] [--csv out.csv] [--size WxH] [--stage auto|none|studio] [--point-light]
//                                [--ism-point-budget P] [--ism-tile-size T] scene.gltf...

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bench_args.h"
#include "evaluation/direct_light_cases.h"
#include "renderer/core/sampling.h"
#include "renderer/gl/context.h"
#include "renderer/gl/preview_renderer.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/offline/path_tracer.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/lights_json.h"
#include "renderer/scene/staging.h"
#include "renderer/vpl/vpl_generation.h"

namespace {

using namespace vplab;
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

// Process CPU time (every thread, the GL driver's included): on a shared machine the wall time of a change grows with
// the load; its CPU time does not, and CPU time / cores bounds the wall time on an idle machine of this kind.
double processCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

// One kind of change (a new VPL set, or a light move) timed over the repeats: wall and process CPU time, and its parts
// (wall ms): VPL generation, the lights' maps, the VPL maps, the direct light, the gather with the merges, the SSBC,
// and what the other passes took. median() gives each part's median.
struct ChangeTimes {
  std::vector<double> wall, cpu, generation, lightMaps, vplMaps, direct, gather, ssbc, other;
  void add(double wallMs, double cpuMs, double generationMs, const PreviewTimings& t) {
    wall.push_back(wallMs);
    cpu.push_back(cpuMs);
    generation.push_back(generationMs);
    lightMaps.push_back(t.directShadowWallMs);
    vplMaps.push_back(t.vplShadowWallMs);
    direct.push_back(t.directWallMs);
    gather.push_back(t.gatherWallMs);
    ssbc.push_back(t.ssbcWallMs);
    other.push_back(t.frameWallMs - t.directShadowWallMs - t.vplShadowWallMs - t.directWallMs - t.gatherWallMs -
                    t.ssbcWallMs);
  }
  ChangeTimes median() const {
    ChangeTimes m;
    for (auto [in, out] : {std::pair{&wall, &m.wall},
                           {&cpu, &m.cpu},
                           {&generation, &m.generation},
                           {&lightMaps, &m.lightMaps},
                           {&vplMaps, &m.vplMaps},
                           {&direct, &m.direct},
                           {&gather, &m.gather},
                           {&ssbc, &m.ssbc},
                           {&other, &m.other}})
      out->push_back(::median(*in));
    return m;
  }
  // The medians' value (after median()), -1 when the change was not measured.
  static double at(const std::vector<double>& v) { return v.empty() ? -1.0 : v.front(); }
};

struct Row {
  std::string scene, visibility;
  int indirectDownscale = 1;
  std::size_t triangles = 0;
  double loadMs = 0, firstMs = 0, referenceMs = 0;
  // Medians of a new VPL set and of a light move.
  ChangeTimes vplChange, lightMove;
};

}  // namespace

int main(int argc, char** argv) {
  GlBackend backend = GlBackend::Auto;
  std::vector<VisibilityMethod> methods = {VisibilityMethod::Cube, VisibilityMethod::Ism};
  std::vector<int> downscales = {1, 2};
  std::vector<std::string> scenes;
  std::string csvPath;
  int repeats = 3, width = 640, height = 480;
  Stage stage = Stage::Auto;
  bool pointLight = false;
  const Settings defaults;
  int ismPointBudget = defaults.ismPointBudget, ismTileSize = defaults.ismTileSize;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--gl") {
      if (!parseGlBackend(benchOptionValue(argc, argv, i), backend)) return std::fprintf(stderr, "bad --gl\n"), 2;
    } else if (a == "--visibility") {
      methods.clear();
      std::stringstream list(benchOptionValue(argc, argv, i));
      for (std::string item; std::getline(list, item, ',');) {
        VisibilityMethod m;
        if (!parseVisibilityMethod(item, m)) return std::fprintf(stderr, "bad --visibility '%s'\n", item.c_str()), 2;
        methods.push_back(m);
      }
    } else if (a == "--indirect-downscale") {
      downscales.clear();
      std::stringstream list(benchOptionValue(argc, argv, i));
      for (std::string item; std::getline(list, item, ',');) downscales.push_back(std::atoi(item.c_str()));
    } else if (a == "--repeats") {
      repeats = std::max(1, std::atoi(benchOptionValue(argc, argv, i).c_str()));
    } else if (a == "--csv") {
      csvPath = benchOptionValue(argc, argv, i);
    } else if (a == "--size") {
      if (std::sscanf(benchOptionValue(argc, argv, i).c_str(), "%dx%d", &width, &height) != 2)
        return std::fprintf(stderr, "bad --size\n"), 2;
    } else if (a == "--stage") {
      if (!parseStage(benchOptionValue(argc, argv, i), stage)) return std::fprintf(stderr, "bad --stage\n"), 2;
    } else if (a == "--point-light") {
      pointLight = true;
    } else if (a == "--ism-point-budget") {
      ismPointBudget = std::atoi(benchOptionValue(argc, argv, i).c_str());
    } else if (a == "--ism-tile-size") {
      ismTileSize = std::atoi(benchOptionValue(argc, argv, i).c_str());
    } else if (a == "--help" || (!a.empty() && a[0] == '-')) {
      std::fprintf(
          stderr,
          "usage: %s [--gl auto|egl|osmesa] [--visibility cube,ism] [--indirect-downscale 1,2] [--repeats R] [--csv F] "
          "[--size WxH] "
          "[--stage auto|none|studio] [--point-light] [--ism-point-budget P] [--ism-tile-size T] scene.gltf...\n",
          argv[0]);
      return a == "--help" ? 0 : 2;
    } else {
      scenes.push_back(a);
    }
  }
  if (scenes.empty()) return std::fprintf(stderr, "%s: give at least one scene\n", argv[0]), 2;

  HeadlessGlContext context(backend);
  std::vector<Row> rows;
  for (const std::string& path : scenes) {
    for (VisibilityMethod method : methods)
      for (int downscale : downscales) {
        Row row;
        row.scene = path.substr(path.find_last_of('/') + 1);
        row.visibility = toString(method);
        row.indirectDownscale = downscale;
        auto t = Clock::now();
        Scene scene = loadScene(path);
        stageScene(scene, stage);
        applyLightsSidecar(scene);
        if (pointLight) addPointLightAbove(scene);
        OfflineScene offline(scene);
        row.loadMs = msSince(t);
        row.triangles = scene.triangles.size();
        Settings s;
        s.width = width;
        s.height = height;
        s.vplCount = 256;
        s.interleave = 4;
        s.ssbcSteps = 2;
        s.clampBound = 20.0f;
        s.visibility = method;
        s.ismPointBudget = ismPointBudget;
        s.ismTileSize = ismTileSize;
        s.indirectDownscale = downscale;
        if (const std::vector<std::string> problems = validateSettings(s, SettingSpelling::Flag); !problems.empty())
          return std::fprintf(stderr, "%s\n", problems.front().c_str()), 2;
        PreviewRenderer renderer;
        t = Clock::now();
        VplSet vpls = generateVpls(offline, s);
        renderer.render(scene, vpls, s, scene.camera);
        row.firstMs = msSince(t);

        ChangeTimes change;
        for (int r = 0; r <= repeats; ++r) {
          // A new VPL set whose positions differ (the maximum bounce alternates) while the direct light stays: the seed
          // would also redraw the direct-light samples and their maps.
          s.vplMaxBounces = r % 2 ? 2 : 31;
          double cpu0 = processCpuMs();
          t = Clock::now();
          VplSet next = generateVpls(offline, s);
          double generated = msSince(t);
          PreviewTimings timings = renderer.render(scene, next, s, scene.camera);
          double ms = msSince(t);
          if (r > 0) change.add(ms, processCpuMs() - cpu0, generated, timings);  // r = 0: warm-up
        }
        row.vplChange = change.median();

        if (!scene.punctualLights.empty()) {
          ChangeTimes move;
          for (int r = 0; r <= repeats; ++r) {
            double cpu0 = processCpuMs();
            t = Clock::now();
            for (PunctualLight& l : scene.punctualLights)
              if (!l.isDirectional()) l.position += glm::vec3(0.02f, 0.0f, 0.0f) * (r % 2 ? -1.0f : 1.0f);
            offline.punctualLightsChanged();
            renderer.invalidateLights();
            const Clock::time_point generation = Clock::now();
            VplSet next = generateVpls(offline, s);
            double generated = msSince(generation);
            PreviewTimings timings = renderer.render(scene, next, s, scene.camera);
            double ms = msSince(t);
            if (r > 0) move.add(ms, processCpuMs() - cpu0, generated, timings);
          }
          row.lightMove = move.median();
        }

        Settings ref;
        ref.width = ref.height = 256;
        ref.samplesPerPixel = 16;
        t = Clock::now();
        {
          OfflineScene fresh(scene);
          renderReference(fresh, ref);
        }
        row.referenceMs = msSince(t);
        rows.push_back(row);
        const ChangeTimes &c = row.vplChange, &m = row.lightMove;
        auto at = ChangeTimes::at;
        std::printf(
            "%-28s %-4s s=%d %9zu tris  load %7.0f  first %8.0f  vpl change %7.0f (cpu %6.0f; generation %5.0f, maps "
            "%6.0f, gather %5.0f, ssbc %5.0f, other %5.0f)  light move %7.0f (cpu %6.0f; maps %6.0f, vpl maps %5.0f, "
            "direct %5.0f, gather %5.0f, ssbc %5.0f)  reference %6.0f ms\n",
            row.scene.c_str(), row.visibility.c_str(), row.indirectDownscale, row.triangles, row.loadMs, row.firstMs,
            at(c.wall), at(c.cpu), at(c.generation), at(c.vplMaps), at(c.gather), at(c.ssbc),
            at(c.other) + at(c.direct) + at(c.lightMaps), at(m.wall), at(m.cpu), at(m.lightMaps), at(m.vplMaps),
            at(m.direct), at(m.gather), at(m.ssbc), row.referenceMs);
        std::fflush(stdout);
      }
  }
  if (!csvPath.empty()) {
    std::ofstream csv(csvPath);
    csv << "scene,visibility,indirect_downscale,triangles,load_ms,first_ms,vpl_change_ms,vpl_change_cpu_ms,generation_"
           "ms,vpl_maps_ms,"
           "gather_ms,ssbc_ms,other_passes_ms,light_move_ms,light_move_cpu_ms,light_maps_ms,light_move_vpl_maps_ms,"
           "light_move_direct_ms,light_move_gather_ms,light_move_ssbc_ms,reference_256_16spp_ms\n";
    for (const Row& r : rows) {
      const ChangeTimes &c = r.vplChange, &m = r.lightMove;
      auto at = ChangeTimes::at;
      csv << r.scene << ',' << r.visibility << ',' << r.indirectDownscale << ',' << r.triangles << ',' << r.loadMs
          << ',' << r.firstMs << ',' << at(c.wall) << ',' << at(c.cpu) << ',' << at(c.generation) << ','
          << at(c.vplMaps) << ',' << at(c.gather) << ',' << at(c.ssbc) << ','
          << at(c.other) + at(c.direct) + at(c.lightMaps) << ',' << at(m.wall) << ',' << at(m.cpu) << ','
          << at(m.lightMaps) << ',' << at(m.vplMaps) << ',' << at(m.direct) << ',' << at(m.gather) << ',' << at(m.ssbc)
          << ',' << r.referenceMs << '\n';
    }
    if (!csv) return std::fprintf(stderr, "cannot write %s\n", csvPath.c_str()), 1;
  }
  return 0;
}
