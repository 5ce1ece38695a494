// The GL preview through participating media (renderer/gl/media_pass.h, docs/benchmarks.md "Preview with media"): what
// a camera move and a new VPL set cost on a scene with fog, per pass, as wall time and as the process's CPU time
// (llvmpipe's threads included: on a shared machine the wall time grows with the load, the CPU time does not, and CPU
// time / cores is a lower bound for the wall time on an idle machine), median of --repeats after a warm-up. Then the
// whole headless preview (context, scene, VPLs, the first frame with its shader compilation, the image read back)
// against the path-traced reference at 256^2 and 16 spp (BVH included), both as wall times in this process.
//
// usage: vplab_bench_gl_media_bench [--gl auto|egl|osmesa] [--size WxH] [--vpls N] [--interleave k] [--downscale s]
//                                   [--clamp b] [--repeats R] [--csv out.csv] [scene.gltf]

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "bench/bench_args.h"
#include "renderer/gl/context.h"
#include "renderer/gl/heap_warmer.h"
#include "renderer/gl/preview_renderer.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/offline/path_tracer.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/vpl/vpl_generation.h"

namespace {

using namespace vplab;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

struct Measured {
  std::vector<double> wall, cpu, gbuffer, direct, vplShadows, gather, media, ssbc;
  void add(const PreviewTimings& t, double cpuMs) {
    wall.push_back(t.frameWallMs);
    cpu.push_back(cpuMs);
    gbuffer.push_back(t.gbufferWallMs);
    direct.push_back(t.directWallMs);
    vplShadows.push_back(t.vplShadowWallMs);
    gather.push_back(t.gatherWallMs);
    media.push_back(t.mediaWallMs);
    ssbc.push_back(t.ssbcWallMs);
  }
};

// Renders once per repeat after `change` (untimed), each render timed as wall and process CPU time.
Measured measure(int repeats, const std::function<PreviewTimings()>& render) {
  render();  // warm-up: shaders compiled, maps built
  Measured m;
  for (int r = 0; r < repeats; ++r) {
    const std::clock_t cpu0 = std::clock();
    const PreviewTimings t = render();
    m.add(t, 1000.0 * static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC);
  }
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  std::string scenePath = "assets/scenes/cornell-fog.gltf", csvPath, glName = "auto";
  int width = 640, height = 480, vplCount = 256, interleave = 4, downscale = 2, repeats = 5;
  float clamp = 20.0f;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto next = [&] { return benchOptionValue(argc, argv, i); };
    if (a == "--gl")
      glName = next();
    else if (a == "--size") {
      const std::string v = next();
      if (std::sscanf(v.c_str(), "%dx%d", &width, &height) != 2 || width < 1 || height < 1) {
        std::fprintf(stderr, "%s: --size takes WxH\n", argv[0]);
        return 2;
      }
    } else if (a == "--vpls")
      vplCount = std::atoi(next().c_str());
    else if (a == "--interleave")
      interleave = std::atoi(next().c_str());
    else if (a == "--downscale")
      downscale = std::atoi(next().c_str());
    else if (a == "--clamp")
      clamp = static_cast<float>(std::atof(next().c_str()));
    else if (a == "--repeats")
      repeats = std::max(1, std::atoi(next().c_str()));
    else if (a == "--csv")
      csvPath = next();
    else if (!a.empty() && a[0] != '-')
      scenePath = a;
    else {
      std::fprintf(stderr,
                   "usage: %s [--gl auto|egl|osmesa] [--size WxH] [--vpls N] [--interleave k] [--downscale s] "
                   "[--clamp b] [--repeats R] [--csv F] [scene.gltf]\n",
                   argv[0]);
      return a == "--help" ? 0 : 2;
    }
  }
  GlBackend backend;
  if (!parseGlBackend(glName, backend)) {
    std::fprintf(stderr, "%s: --gl takes auto, egl or osmesa\n", argv[0]);
    return 2;
  }
  Settings s;
  s.width = width;
  s.height = height;
  s.vplCount = vplCount;
  s.interleave = interleave;
  s.indirectDownscale = downscale;
  s.clampBound = clamp;
  s.ssbcSteps = 2;

  // The whole headless preview, cold, then the reference it replaces.
  double previewMs = 0.0, referenceMs = 0.0;
  {
    const auto start = std::chrono::steady_clock::now();
    // As vplab preview does: the first frame's textures land in heap warmed on the idle core (heap_warmer.h).
    HeapWarmer warmer(previewFirstFrameBytes(s));
    HeadlessGlContext context(backend);
    OfflineScene offline(loadScene(scenePath));
    const VplSet vpls = generateVpls(offline, s);
    PreviewRenderer renderer;
    renderer.render(offline.scene(), vpls, s, offline.scene().camera);
    const Image image = renderer.readLinear();
    previewMs = msSince(start);
    if (image.pixels.empty()) return 1;
  }
  {
    const auto start = std::chrono::steady_clock::now();
    OfflineScene offline(loadScene(scenePath));
    Settings r;
    r.width = r.height = 256;
    r.samplesPerPixel = 16;
    renderReference(offline, r);
    referenceMs = msSince(start);
  }

  HeadlessGlContext context(backend);
  OfflineScene offline(loadScene(scenePath));
  const Scene& scene = offline.scene();
  VplSet sets[2] = {generateVpls(offline, s), {}};
  Settings other = s;
  other.seed = s.seed + 1;
  sets[1] = generateVpls(offline, other);
  PreviewRenderer renderer;
  Camera cameras[2] = {scene.camera, scene.camera};
  cameras[1].position += 0.01f * glm::normalize(glm::cross(scene.camera.forward, scene.camera.up));
  int step = 0;
  const Measured cameraMove = measure(repeats, [&] {
    ++step;
    return renderer.render(scene, sets[0], s, cameras[step % 2]);
  });
  const Measured vplChange = measure(repeats, [&] {
    ++step;
    return renderer.render(scene, sets[step % 2], s, cameras[0]);
  });

  std::printf("%s, %dx%d, %zu VPLs, k = %d, s = %d, b = %g, %s; median of %d after a warm-up (ms)\n\n",
              scenePath.c_str(), width, height, sets[0].vpls.size(), interleave, downscale, clamp,
              context.description().c_str(), repeats);
  std::printf("| change | wall | CPU | G-buffer | direct | VPL maps | gather | media | SSBC |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  std::ofstream csv;
  if (!csvPath.empty()) {
    csv.open(csvPath);
    csv << "scene,change,wall_ms,cpu_ms,gbuffer_ms,direct_ms,vpl_maps_ms,gather_ms,media_ms,ssbc_ms\n";
  }
  for (const auto& [name, m] : {std::pair<const char*, const Measured&>{"camera move", cameraMove},
                                std::pair<const char*, const Measured&>{"VPL set", vplChange}}) {
    std::printf("| %s | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f |\n", name, median(m.wall), median(m.cpu),
                median(m.gbuffer), median(m.direct), median(m.vplShadows), median(m.gather), median(m.media),
                median(m.ssbc));
    if (csv)
      csv << scenePath << "," << name << "," << median(m.wall) << "," << median(m.cpu) << "," << median(m.gbuffer)
          << "," << median(m.direct) << "," << median(m.vplShadows) << "," << median(m.gather) << "," << median(m.media)
          << "," << median(m.ssbc) << "\n";
  }
  // What virtual ray lights would need in the preview (docs/methods.md "Participating media in the preview"): their
  // count per set, against the VPLs whose maps the set's change costs.
  std::size_t inMedium = 0;
  for (const Vpl& v : sets[0].vpls) inMedium += v.inMedium;
  std::printf("\nset of %zu VPLs (%zu in media) holds %zu VRLs; VPL maps %.2f ms per VPL\n", sets[0].vpls.size(),
              inMedium, sets[0].vrls.size(), median(vplChange.vplShadows) / static_cast<double>(sets[0].vpls.size()));
  std::printf(
      "\nwhole headless preview (context, scene, VPLs, first frame, read back): %.0f ms; reference 256^2, 16 "
      "spp: %.0f ms; ratio %.2f\n",
      previewMs, referenceMs, previewMs / referenceMs);
  if (csv) csv << scenePath << ",whole preview vs reference," << previewMs << "," << referenceMs << ",,,,,,\n";
  return 0;
}
