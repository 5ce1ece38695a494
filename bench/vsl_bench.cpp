// Virtual spherical lights: the error of the preview's deterministic cone integral and what VSLs cost against point
// VPLs, in GL and on the CPU (docs/methods.md "r — virtual spherical lights", docs/benchmarks.md).
//
//   1. Approximation error per (camera point, VPL) pair: the transfer T of renderer/vpl/vsl_integral.h
//      (vslApproxTransfer, what shaders/common/vsl.glsl evaluates) against brute-force integration over the cone
//      (vslTransferNumerical, 96^2 directions), unoccluded, on a grid of camera points x every 4th VPL. "bias" is
//      sum(approx - exact) / sum(exact) over the pairs (what the image mean sees), "mean |err|" is
//      sum |approx - exact| / sum(exact), both of Phi T's luminance.
//   2. Images at 128^2: the GL preview's indirect light against the exact CPU VSL render of the same VPLs (two
//      renders with different pixel seeds, averaged); "cpu noise" is the relMSE between those two renders, the
//      floor under which the comparison cannot go.
//   3. Speed at each size: the GL gather pass (median of --frames steady-state frames, GPU time of the pass with its
//      de-interleave) and the exact CPU render at --spp samples per pixel, point VPLs (b = inf) against VSLs. Each is
//      also given as the process CPU time (all threads, llvmpipe's included; the minimum over the repetitions), which
//      other processes on a shared machine disturb much less than the wall clock: the ratios come from these. A GL
//      frame renders only the indirect component without SSBC, so the gather is nearly all of its CPU time.
//
// usage: vplab_bench_vsl_bench [--gl auto|egl|osmesa] [--vpls N] [--radius r] [--frames F] [--spp S]
//                              [--repeats R] [--csv out.csv] [--quick]

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <string>
#include <vector>

#include "bench/bench_args.h"
#include "renderer/gl/context.h"
#include "renderer/gl/preview_renderer.h"
#include "renderer/image/metrics.h"
#include "renderer/offline/embree_scene.h"
#include "renderer/offline/light_sampler.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/offline/progressive.h"
#include "renderer/offline/vpl_renderer.h"
#include "renderer/scene/brdf_params.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/vpl/vpl_generation.h"
#include "renderer/vpl/vsl_integral.h"

namespace {

using namespace vplab;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

double seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

struct PairError {
  double bias = 0.0, meanAbs = 0.0;
  std::size_t pairs = 0;
};

PairError pairError(const OfflineScene& l, const VplSet& vpls, int grid) {
  std::vector<VslEnd> ends;
  for (const Vpl& v : vpls.vpls)
    ends.push_back({v.position, v.normal, v.geometricNormal, v.incoming, brdfParamsAt(l.scene(), v.material, v.uv)});
  double sumExact = 0.0, sumDiff = 0.0, sumAbs = 0.0;
  PairError e;
  for (int y = 0; y < grid; ++y)
    for (int x = 0; x < grid; ++x) {
      glm::vec3 dir = cameraRayDirection(l.scene().camera, x + 0.5f, y + 0.5f, grid, grid);
      std::optional<SurfaceHit> hit = l.embree().intersect(l.scene().camera.position, dir);
      if (!hit || glm::dot(hit->geometricNormal, -dir) <= 0.0f) continue;
      VslEnd x1{hit->position, hit->shadingNormal, hit->geometricNormal, -dir,
                brdfParamsAt(l.scene(), hit->material, hit->uv)};
      for (std::size_t i = 0; i < ends.size(); i += 4) {
        float r = vpls.vpls[i].radius;
        double exact = luminance(vpls.vpls[i].flux * vslTransferNumerical(x1, ends[i], r, 96));
        double approx = luminance(vpls.vpls[i].flux * vslApproxTransfer(x1, ends[i], r));
        sumExact += exact;
        sumDiff += approx - exact;
        sumAbs += std::abs(approx - exact);
        ++e.pairs;
      }
    }
  e.bias = sumExact > 0.0 ? sumDiff / sumExact : 0.0;
  e.meanAbs = sumExact > 0.0 ? sumAbs / sumExact : 0.0;
  return e;
}

Image average(const Image& a, const Image& b) {
  Image out = a;
  for (std::size_t i = 0; i < out.pixels.size(); ++i) out.pixels[i] = 0.5f * (a.pixels[i] + b.pixels[i]);
  return out;
}

double processCpuSeconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

struct Timing {
  double ms = 0.0;     ///< GL: median gather GPU time; CPU: median wall time
  double cpuMs = 0.0;  ///< minimum process CPU time
};

Timing gatherTiming(PreviewRenderer& renderer, const OfflineScene& l, const VplSet& vpls, const Settings& s,
                    int frames) {
  renderer.render(l.scene(), vpls, s, l.scene().camera);  // compiles, renders the shadow maps
  renderer.invalidateFrame();
  renderer.render(l.scene(), vpls, s, l.scene().camera);
  std::vector<double> ms;
  Timing t;
  t.cpuMs = 1e30;
  for (int f = 0; f < frames; ++f) {
    renderer.invalidateFrame();
    double c0 = processCpuSeconds();
    ms.push_back(renderer.render(l.scene(), vpls, s, l.scene().camera).gatherMs);
    t.cpuMs = std::min(t.cpuMs, 1e3 * (processCpuSeconds() - c0));
  }
  t.ms = median(ms);
  return t;
}

Timing cpuTiming(const OfflineScene& l, const VplSet& vpls, Method method, const Settings& s, int repeats) {
  std::vector<double> ms;
  Timing t;
  t.cpuMs = 1e30;
  for (int i = 0; i < repeats; ++i) {
    auto start = std::chrono::steady_clock::now();
    double c0 = processCpuSeconds();
    renderVpl(l, vpls, method, s);
    t.cpuMs = std::min(t.cpuMs, 1e3 * (processCpuSeconds() - c0));
    ms.push_back(1e3 * seconds(start));
  }
  t.ms = median(ms);
  return t;
}

VplSet withRadius(VplSet set, float r) {
  for (Vpl& v : set.vpls) v.radius = r;
  return set;
}

}  // namespace

int main(int argc, char** argv) {
  GlBackend backend = GlBackend::Auto;
  int vplCount = 256, frames = 5, spp = 1, repeats = 2;
  float radius = 0.03f;
  bool quick = false;
  std::string csvPath = "vsl_bench.csv";
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--gl") {
      if (!parseGlBackend(benchOptionValue(argc, argv, i), backend)) return 2;
    } else if (a == "--vpls") {
      vplCount = std::max(1, std::atoi(benchOptionValue(argc, argv, i).c_str()));
    } else if (a == "--radius") {
      radius = std::max(0.0f, static_cast<float>(std::atof(benchOptionValue(argc, argv, i).c_str())));
    } else if (a == "--frames") {
      frames = std::max(1, std::atoi(benchOptionValue(argc, argv, i).c_str()));
    } else if (a == "--repeats") {
      repeats = std::max(1, std::atoi(benchOptionValue(argc, argv, i).c_str()));
    } else if (a == "--spp") {
      spp = std::max(1, std::atoi(benchOptionValue(argc, argv, i).c_str()));
    } else if (a == "--csv") {
      csvPath = benchOptionValue(argc, argv, i);
    } else if (a == "--quick") {
      quick = true;
    } else {
      std::fprintf(stderr,
                   "usage: %s [--gl auto|egl|osmesa] [--vpls N] [--radius r] [--frames F] [--spp S] "
                   "[--repeats R] [--csv F] [--quick]\n",
                   argv[0]);
      return 2;
    }
  }
  HeadlessGlContext context(backend);
  const std::vector<std::string> scenes = {"cornell-box", "cornell-glossy"};
  std::vector<std::pair<int, int>> sizes = {{256, 256}, {640, 480}};
  if (quick) sizes = {{128, 128}};
  std::ofstream csv(csvPath);
  csv << "scene,vpls,radius,pairs,pair_bias,pair_mean_abs,gl_vs_cpu_relmse,gl_vs_cpu_energy,cpu_noise_relmse,width,"
         "height,gl_point_ms,gl_vsl_ms,gl_point_cpu_ms,gl_vsl_cpu_ms,cpu_spp,cpu_point_ms,cpu_vsl_ms,cpu_point_cpu_ms,"
         "cpu_vsl_cpu_ms\n";
  std::printf("gl %s, N = %d, r = %g m, %d GL frames, CPU %d spp x %d repeats (threads: all cores)\n\n",
              toString(backend), vplCount, radius, frames, spp, repeats);
  std::printf("%-15s %7s %8s %10s | %11s %8s %10s\n", "scene", "pairs", "bias", "mean |err|", "GL vs CPU", "energy",
              "cpu noise");
  std::vector<std::string> speedLines;
  for (const std::string& name : scenes) {
    OfflineScene l(loadScene(std::string(VPLAB_ASSET_DIR) + "/scenes/" + name + ".gltf"));
    Settings s;
    s.vplCount = vplCount;
    s.threads = 0;
    s.components = Components::Indirect;
    s.vslRadius = radius;
    VplSet vsls = generateVpls(l, s);
    VplSet points = withRadius(vsls, 0.0f);

    // 1. Approximation error per pair.
    PairError pe = pairError(l, vsls, quick ? 8 : 24);

    // 2. Images at 128^2.
    s.width = s.height = 128;
    PreviewRenderer renderer;
    renderer.render(l.scene(), vsls, s, l.scene().camera);
    Image gl = renderer.readLinear(PreviewOutput::Indirect);
    s.samplesPerPixel = quick ? 2 : 8;
    Image cpuA = renderVpl(l, vsls, Method::Vsl, s).image;
    s.seed = 2;
    Image cpuB = renderVpl(l, vsls, Method::Vsl, s).image;
    s.seed = 1;
    ImageMetrics m = compareImages(gl, average(cpuA, cpuB));
    double noise = compareImages(cpuA, cpuB).relMse;
    std::printf("%-15s %7zu %+7.2f%% %9.2f%% | %11.5f %8.4f %10.5f\n", name.c_str(), pe.pairs, 100.0 * pe.bias,
                100.0 * pe.meanAbs, m.relMse, m.energyRatioOverall, noise);

    // 3. Speed.
    for (auto [w, h] : sizes) {
      Settings t = s;
      t.width = w;
      t.height = h;
      t.samplesPerPixel = spp;
      t.clampBound = kInfinity;
      Timing glPoint = gatherTiming(renderer, l, points, t, frames);
      Timing glVsl = gatherTiming(renderer, l, vsls, t, frames);
      Timing cpuPoint = cpuTiming(l, points, Method::Vpl, t, repeats);
      Timing cpuVsl = cpuTiming(l, vsls, Method::Vsl, t, repeats);
      char line[256];
      std::snprintf(line, sizeof(line), "%-15s %4dx%-4d %8.0f %8.0f %8.0f %8.0f %6.2fx | %8.2f %8.2f %8.2f %8.2f %6.2fx",
                    name.c_str(), w, h, glPoint.ms, glVsl.ms, glPoint.cpuMs, glVsl.cpuMs, glVsl.cpuMs / glPoint.cpuMs,
                    cpuPoint.ms / 1e3, cpuVsl.ms / 1e3, cpuPoint.cpuMs / 1e3, cpuVsl.cpuMs / 1e3,
                    cpuVsl.cpuMs / cpuPoint.cpuMs);
      speedLines.push_back(line);
      csv << name << ',' << vsls.vpls.size() << ',' << radius << ',' << pe.pairs << ',' << pe.bias << ','
          << pe.meanAbs << ',' << m.relMse << ',' << m.energyRatioOverall << ',' << noise << ',' << w << ',' << h
          << ',' << glPoint.ms << ',' << glVsl.ms << ',' << glPoint.cpuMs << ',' << glVsl.cpuMs << ',' << spp << ','
          << cpuPoint.ms << ',' << cpuVsl.ms << ',' << cpuPoint.cpuMs << ',' << cpuVsl.cpuMs << '\n';
    }
  }
  std::printf("\n%-15s %9s %8s %8s %8s %8s %7s | %8s %8s %8s %8s %7s\n", "", "", "GL point", "GL VSL", "point",
              "VSL", "ratio", "CPU pt", "CPU VSL", "point", "VSL", "ratio");
  std::printf("%-15s %9s %8s %8s %8s %8s %7s | %8s %8s %8s %8s %7s\n", "scene", "size", "gpu ms", "gpu ms", "cpu ms",
              "cpu ms", "(cpu)", "wall s", "wall s", "cpu s", "cpu s", "(cpu)");
  for (const std::string& line : speedLines) std::printf("%s\n", line.c_str());
  std::printf("\nwrote %s\n", csvPath.c_str());
  return 0;
}
