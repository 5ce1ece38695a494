// GL preview benchmark: per-pass GPU times (GL_TIME_ELAPSED) and frames/s of the headless preview on the Cornell box
// for N VPLs x interleave k, plus the gather pass's pixel x VPL evaluations/s. A "frame" is what a camera move costs
// (G-buffer, direct, gather, SSBC; VPL shadow maps are kept); shadow-map time is reported on its own.
// Every configuration is warmed up first (llvmpipe compiles shaders on first use), then timed
// over several frames; the table shows the median frame.
// Beside every configuration, on the same context and at the same size, a ceiling probe
// (shaders/bench/ceiling_probe.frag.glsl: per pixel and light 2 UBO reads + 1 shadow fetch + ~40 flops)
// runs the same number of pixel x light evaluations as the gather; "of ceiling" is the gather's
// evaluation rate over the probe's. The probe is timed with glFinish and the wall clock (llvmpipe's first timer query
// is unreliable), median of 5 draws after a warm-up draw. The gather's time includes the geometry-aware de-interleave
// ("merge"); "draws" is the rate of the gather's own draws, without it, over the probe's.
//
// Each configuration runs with each VPL visibility technique of --visibility (default cube,ism): "vis" column.
//
// usage: vplab_bench_gl_bench [--gl auto|egl|osmesa] [--size WxH] [--frames F] [--csv out.csv] [--scene file.gltf]
//                             [--ssbc S] [--clamp b] [--ssbc-coarse-rings 0|1] [--indirect-downscale s]
//                             [--visibility cube,ism] [--quick]

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bench_args.h"
#include "renderer/gl/context.h"
#include "renderer/gl/preview_renderer.h"
#include "renderer/gl/resources.h"
#include "renderer/gl/shader.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/vpl/vpl_generation.h"

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

// The fragment-shading ceiling probe and what it draws with; sizes match ceiling_probe.frag.glsl.
class CeilingProbe {
 public:
  static constexpr int kLights = 1024, kCubes = 16, kFace = 128;

  CeilingProbe(int width, int height)
      : program_({"preview/fullscreen.vert.glsl", "bench/ceiling_probe.frag.glsl"}),
        target_(width, height, vplab::TextureFormat::Rgba32F),
        shadows_(kFace, kFace, vplab::TextureFormat::Depth32F, 1, 6 * kCubes),
        width_(width),
        height_(height) {
    targetFramebuffer_.attachColor(0, target_);
    targetFramebuffer_.finalize(1);
    shadows_.setDepthCompare(true);
    shadows_.setLinearFiltering(true);
    vplab::GlFramebuffer clear;
    clear.attachDepth(shadows_, 0, -1);
    clear.clearDepth(1.0f);  // every fetch passes the comparison: the sum stays non-zero
    // Lights above the receiver plane z = -1, facing it, so that both cosines are positive.
    std::vector<glm::vec4> table;
    for (int j = 0; j < kLights; ++j) {
      float t = (static_cast<float>(j) + 0.5f) / kLights;
      table.emplace_back(std::cos(40.0f * t), std::sin(40.0f * t), 0.5f + t, 20.0f);
      table.emplace_back(glm::normalize(glm::vec3(0.1f * t, -0.1f * t, -1.0f)), 1.0f + t);
    }
    lights_ = vplab::GlBuffer(table.size() * sizeof(glm::vec4), table.data());
    program_.set("uInvSize", glm::vec2(1.0f / width, 1.0f / height));
  }

  // Median wall milliseconds of one full-screen draw with `lightCount` lights per pixel; meanOut receives the mean
  // of the written sums (finite and non-zero unless the work was dropped).
  double measure(int lightCount, double& meanOut) {
    program_.set("uLightCount", lightCount);
    targetFramebuffer_.bind(width_, height_);
    shadows_.bind(6);
    lights_.bindUniform(1);
    program_.use();
    vao_.bind();
    std::vector<double> ms;
    for (int i = 0; i < 6; ++i) {
      vplab::glFinishAll();
      auto start = std::chrono::steady_clock::now();
      vplab::drawProceduralTriangles(3);
      vplab::glFinishAll();
      double t = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      if (i > 0) ms.push_back(t);  // the first draw is the warm-up
    }
    std::vector<glm::vec4> pixels = vplab::readFramebufferRgba(targetFramebuffer_, 0, width_, height_);
    double sum = 0.0;
    for (const glm::vec4& p : pixels) sum += p.x;
    meanOut = sum / static_cast<double>(pixels.size());
    vplab::checkGlError("ceiling probe");
    return median(ms);
  }

 private:
  vplab::ShaderProgram program_;
  vplab::GlTexture target_;
  vplab::GlFramebuffer targetFramebuffer_;
  vplab::GlTexture shadows_;
  vplab::GlBuffer lights_;
  vplab::GlVertexArray vao_;
  int width_, height_;
};

}  // namespace

int main(int argc, char** argv) {
  using namespace vplab;
  std::string scenePath = std::string(VPLAB_ASSET_DIR) + "/scenes/cornell-box.gltf";
  std::string csvPath = "gl_bench.csv";
  GlBackend backend = GlBackend::Auto;
  int width = 640, height = 480, frames = 5, ssbc = 2, ssbcCoarseRings = 1, downscale = 1;
  int shadowMapSize = Settings{}.shadowMapSize;
  float clamp = 20.0f;
  bool quick = false;
  std::vector<VisibilityMethod> methods = {VisibilityMethod::Cube, VisibilityMethod::Ism};
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto next = [&] { return benchOptionValue(argc, argv, i); };
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
    } else if (a == "--ssbc-coarse-rings") {
      ssbcCoarseRings = std::atoi(next().c_str());
    } else if (a == "--indirect-downscale") {
      downscale = std::atoi(next().c_str());
      if (downscale < 1 || downscale > 4) return std::fprintf(stderr, "gl_bench: --indirect-downscale is 1 to 4\n"), 2;
    } else if (a == "--shadow-map-size") {
      shadowMapSize = std::atoi(next().c_str());
      if (shadowMapSize < 16 || shadowMapSize > 4096)
        return std::fprintf(stderr, "gl_bench: --shadow-map-size is 16 to 4096\n"), 2;
    } else if (a == "--quick") {
      quick = true;
    } else if (a == "--visibility") {
      methods.clear();
      std::stringstream list(next());
      for (std::string item; std::getline(list, item, ',');) {
        VisibilityMethod m;
        if (!parseVisibilityMethod(item, m))
          return std::fprintf(stderr, "gl_bench: bad --visibility '%s'\n", item.c_str()), 2;
        methods.push_back(m);
      }
    } else {
      std::fprintf(stderr,
                   "usage: %s [--gl auto|egl|osmesa] [--size WxH] [--frames F] [--csv F] [--scene F] "
                   "[--ssbc S] [--clamp b] [--ssbc-coarse-rings 0|1] [--indirect-downscale s] [--shadow-map-size S] "
                   "[--visibility cube,ism] [--quick]\n",
                   argv[0]);
      return a == "--help" ? 0 : 2;
    }
  }

  Scene scene = loadScene(scenePath);
  OfflineScene offline(scene);
  HeadlessGlContext context(backend);
  std::printf(
      "gl      %s\nscene   %s, %dx%d, b = %g, ssbc %d (coarse rings %s), indirect light on a 1/%d grid, VPL "
      "maps %d (%d^2 per face), median of %d frames after warm-up\n\n",
      context.description().c_str(), scene.sourcePath.c_str(), width, height, clamp, ssbc,
      ssbcCoarseRings != 0 ? "on" : "off", downscale, shadowMapSize, shadowMapSize / 2, frames);

  std::ofstream csv(csvPath);
  csv << "visibility,vpls,k,frame_ms,fps,gbuffer_ms,direct_ms,gather_ms,ssbc_ms,vpl_shadow_ms,frame_wall_ms,"
         "gather_evals,gather_gevals_per_s,probe_lights,probe_ms,probe_gevals_per_s,gather_of_ceiling,deinterleave_ms,"
         "gather_draws_of_ceiling\n";
  std::printf("%4s %6s %3s %9s %7s %8s %8s %8s %8s %10s %9s %10s %6s %9s %9s %8s %6s %7s\n", "vis", "VPLs", "k",
              "frame ms", "fps", "gbuffer", "direct", "gather", "ssbc", "vpl shadow", "wall ms", "gather G/s", "probe",
              "probe ms", "probe G/s", "ceiling", "merge", "draws");
  // The gather runs on the indirect light's grid: the probe runs on as many pixels.
  const glm::ivec2 grid = indirectGridSize(width, height, downscale);
  const int gridWidth = grid.x, gridHeight = grid.y;
  CeilingProbe probe(gridWidth, gridHeight);
  std::vector<int> counts = quick ? std::vector<int>{256} : std::vector<int>{64, 256, 1024};
  std::vector<int> ks = quick ? std::vector<int>{4} : std::vector<int>{1, 2, 4};
  for (VisibilityMethod method : methods) {
    for (int n : counts) {
      Settings settings;
      settings.visibility = method;
      settings.width = width;
      settings.height = height;
      settings.vplCount = n;
      settings.clampBound = clamp;
      settings.ssbcSteps = ssbc;
      settings.ssbcCoarseRings = ssbcCoarseRings != 0;
      settings.indirectDownscale = downscale;
      settings.shadowMapSize = shadowMapSize;
      VplSet vpls = generateVpls(offline, settings);
      PreviewRenderer renderer;
      double shadowMs = 0.0;  // VPL shadow maps are rendered once per VPL set, with the first k
      for (int k : ks) {
        settings.interleave = k;
        PreviewTimings first = renderer.render(scene, vpls, settings, scene.camera);
        if (first.vplShadowMs > 0.0) shadowMs = first.vplShadowMs;
        // Warm-up: every pass once more with this k (first use compiles the shader variants).
        renderer.invalidateFrame();
        renderer.render(scene, vpls, settings, scene.camera);
        std::vector<double> frame, gb, di, ga, ss, wall, merge;
        double evals = 0.0;
        for (int f = 0; f < frames; ++f) {
          renderer.invalidateFrame();
          PreviewTimings t = renderer.render(scene, vpls, settings, scene.camera);
          frame.push_back(t.gbufferMs + t.directMs + t.gatherMs + t.ssbcMs);
          gb.push_back(t.gbufferMs);
          di.push_back(t.directMs);
          ga.push_back(t.gatherMs);
          ss.push_back(t.ssbcMs);
          wall.push_back(t.frameWallMs);
          merge.push_back(t.deinterleaveMs);
          evals = t.gatherEvaluations;
        }
        double fm = median(frame), gm = median(ga);
        double rate = gm > 0.0 ? evals / (gm * 1e6) : 0.0;
        // Ceiling probe over the same pixel x light evaluations (lights per pixel = N / k^2, rounded).
        int probeLights =
            std::max(1, static_cast<int>(std::lround(evals / (static_cast<double>(gridWidth) * gridHeight))));
        double probeMean = 0.0;
        double probeMs = probe.measure(probeLights, probeMean);
        double probeEvals = static_cast<double>(gridWidth) * gridHeight * probeLights;
        double probeRate = probeMs > 0.0 ? probeEvals / (probeMs * 1e6) : 0.0;
        double ofCeiling = probeRate > 0.0 ? rate / probeRate : 0.0;
        // The gather's own draws, without the de-interleave that its time includes.
        double mm = median(merge);
        double drawsOfCeiling = probeRate > 0.0 && gm > mm ? evals / ((gm - mm) * 1e6) / probeRate : 0.0;
        if (!(probeMean > 0.0) || !std::isfinite(probeMean))
          std::fprintf(stderr, "gl_bench: ceiling probe wrote %g: its work was not done\n", probeMean);
        std::printf(
            "%4s %6zu %3d %9.1f %7.2f %8.1f %8.1f %8.1f %8.1f %10.1f %9.1f %10.3f %6d %9.1f %9.3f %7.0f%% %6.1f "
            "%6.0f%%\n",
            toString(method), vpls.vpls.size(), k, fm, 1000.0 / fm, median(gb), median(di), gm, median(ss), shadowMs,
            median(wall), rate, probeLights, probeMs, probeRate, 100.0 * ofCeiling, mm, 100.0 * drawsOfCeiling);
        csv << toString(method) << ',' << vpls.vpls.size() << ',' << k << ',' << fm << ',' << 1000.0 / fm << ','
            << median(gb) << ',' << median(di) << ',' << gm << ',' << median(ss) << ',' << shadowMs << ','
            << median(wall) << ',' << evals << ',' << rate << ',' << probeLights << ',' << probeMs << ',' << probeRate
            << ',' << ofCeiling << ',' << mm << ',' << drawsOfCeiling << '\n';
      }
    }
  }
  std::printf("\nwrote %s\n", csvPath.c_str());
  return 0;
}
