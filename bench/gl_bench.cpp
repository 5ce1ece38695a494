// GL preview benchmark: per-pass GPU times (GL_TIME_ELAPSED) and frames/s of the headless preview on the Cornell box
// for N VPLs x interleave k, plus the gather pass's pixel x VPL evaluations/s. A "frame" is what a camera move costs
// (G-buffer, direct, gather, SSBC, tonemap; VPL shadow maps are kept); shadow-map time is reported on its own.
// Every configuration is warmed up first (llvmpipe compiles shaders on first use, STACK.md pitfall 5), then timed
// over several frames; the table shows the median frame.
//
// usage: vplab_bench_gl_bench [--gl auto|egl|osmesa] [--size WxH] [--frames F] [--csv out.csv] [--scene file.gltf]
//                             [--ssbc S] [--clamp b] [--ssbc-divisor 1|2] [--quick]

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "renderer/gl/context.h"
#include "renderer/gl/preview_renderer.h"
#include "renderer/offline/embree_scene.h"
#include "renderer/offline/light_sampler.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/vpl/vpl_generation.h"

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  using namespace vplab;
  std::string scenePath = std::string(VPLAB_ASSET_DIR) + "/scenes/cornell-box.gltf";
  std::string csvPath = "gl_bench.csv";
  GlBackend backend = GlBackend::Auto;
  int width = 640, height = 480, frames = 5, ssbc = 2, ssbcDivisor = 1;
  float clamp = 20.0f;
  bool quick = false;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "gl_bench: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--gl") {
      if (!parseGlBackend(next(), backend)) return std::fprintf(stderr, "gl_bench: bad --gl\n"), 2;
    } else if (a == "--size") {
      if (std::sscanf(next().c_str(), "%dx%d", &width, &height) != 2)
        return std::fprintf(stderr, "gl_bench: bad --size\n"), 2;
    } else if (a == "--frames") {
      frames = std::max(1, std::atoi(next().c_str()));
    } else if (a == "--csv") {
      csvPath = next();
    } else if (a == "--scene") {
      scenePath = next();
    } else if (a == "--ssbc") {
      ssbc = std::atoi(next().c_str());
    } else if (a == "--clamp") {
      clamp = std::strtof(next().c_str(), nullptr);
    } else if (a == "--ssbc-divisor") {
      ssbcDivisor = std::atoi(next().c_str());
    } else if (a == "--quick") {
      quick = true;
    } else {
      std::fprintf(stderr,
                   "usage: %s [--gl auto|egl|osmesa] [--size WxH] [--frames F] [--csv F] [--scene F] "
                   "[--ssbc S] [--clamp b] [--ssbc-divisor 1|2] [--quick]\n",
                   argv[0]);
      return a == "--help" ? 0 : 2;
    }
  }

  Scene scene = loadScene(scenePath);
  EmbreeScene embree(scene);
  LightSampler lights(scene);
  HeadlessGlContext context(backend);
  std::printf("gl      %s\nscene   %s, %dx%d, b = %g, ssbc %d (resolution / %d), median of %d frames after warm-up\n\n",
              context.description().c_str(), scene.sourcePath.c_str(), width, height, clamp, ssbc, ssbcDivisor, frames);

  std::ofstream csv(csvPath);
  csv << "vpls,k,frame_ms,fps,gbuffer_ms,direct_ms,gather_ms,ssbc_ms,tonemap_ms,vpl_shadow_ms,frame_wall_ms,"
         "gather_evals,gather_gevals_per_s\n";
  std::printf("%6s %3s %9s %7s %8s %8s %8s %8s %8s %10s %9s %10s\n", "VPLs", "k", "frame ms", "fps", "gbuffer",
              "direct", "gather", "ssbc", "tonemap", "vpl shadow", "wall ms", "gather G/s");
  std::vector<int> counts = quick ? std::vector<int>{256} : std::vector<int>{64, 256, 1024};
  std::vector<int> ks = quick ? std::vector<int>{4} : std::vector<int>{1, 2, 4};
  for (int n : counts) {
    Settings settings;
    settings.width = width;
    settings.height = height;
    settings.vplCount = n;
    settings.clampBound = clamp;
    settings.ssbcSteps = ssbc;
    settings.ssbcResolutionDivisor = ssbcDivisor;
    VplSet vpls = generateVpls(scene, embree, lights, settings);
    PreviewRenderer renderer;
    double shadowMs = 0.0;  // VPL shadow maps are rendered once per VPL set, with the first k
    for (int k : ks) {
      settings.interleave = k;
      PreviewTimings first = renderer.render(scene, vpls, settings, scene.camera);
      if (first.vplShadowMs > 0.0) shadowMs = first.vplShadowMs;
      // Warm-up: every pass once more with this k (first use compiles the shader variants).
      renderer.invalidateFrame();
      renderer.render(scene, vpls, settings, scene.camera);
      std::vector<double> frame, gb, di, ga, ss, tm, wall;
      double evals = 0.0;
      for (int f = 0; f < frames; ++f) {
        renderer.invalidateFrame();
        PreviewTimings t = renderer.render(scene, vpls, settings, scene.camera);
        frame.push_back(t.gbufferMs + t.directMs + t.gatherMs + t.ssbcMs + t.tonemapMs);
        gb.push_back(t.gbufferMs);
        di.push_back(t.directMs);
        ga.push_back(t.gatherMs);
        ss.push_back(t.ssbcMs);
        tm.push_back(t.tonemapMs);
        wall.push_back(t.frameWallMs);
        evals = t.gatherEvaluations;
      }
      double fm = median(frame), gm = median(ga);
      double rate = gm > 0.0 ? evals / (gm * 1e6) : 0.0;
      std::printf("%6zu %3d %9.1f %7.2f %8.1f %8.1f %8.1f %8.1f %8.1f %10.1f %9.1f %10.3f\n", vpls.vpls.size(), k, fm,
                  1000.0 / fm, median(gb), median(di), gm, median(ss), median(tm), shadowMs, median(wall), rate);
      csv << vpls.vpls.size() << ',' << k << ',' << fm << ',' << 1000.0 / fm << ',' << median(gb) << ',' << median(di)
          << ',' << gm << ',' << median(ss) << ',' << median(tm) << ',' << shadowMs << ',' << median(wall) << ','
          << evals << ',' << rate << '\n';
    }
  }
  std::printf("\nwrote %s\n", csvPath.c_str());
  return 0;
}
