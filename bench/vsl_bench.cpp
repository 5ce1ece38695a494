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
//   3. The error split of item 2 at the test's setting (128^2, 64 VPLs; tests/gl_accuracy_test.cpp), on the scene
//      and on copies whose glossy materials take another roughness: images at the pixel centres with exact (Embree)
//      visibility, one with T by brute force (vslTransferNumerical, --split-grid^2 directions), one with the
//      approximation. "approx" compares those two (the approximation alone), "shadow maps" the GL image with the
//      approximation's (shadow-map visibility, float differences), "footprint+noise" the brute-force image with the
//      CPU render (a pixel's jittered footprint against its centre, and the estimator's noise).
//   4. Speed at each size: the GL gather pass (median of --frames steady-state frames, GPU time of the pass with its
//      de-interleave) and the exact CPU render at --spp samples per pixel, point VPLs (b = inf) against VSLs. Each is
//      also given as the process CPU time (all threads, llvmpipe's included; the minimum over the repetitions), which
//      other processes on a shared machine disturb much less than the wall clock. The GL rows give two ratios: of the
//      gather pass's GPU time (what a VSL adds to the pass it changes; on a quiet machine) and of the frame's CPU time
//      (a GL frame renders only the indirect component without SSBC, so the G-buffer and the direct light are the
//      rest; steadier on a shared machine). Point and VSL frames alternate, so that a change of load touches both.
//
// usage: vplab_bench_vsl_bench [--gl auto|egl|osmesa] [--vpls N] [--radius r] [--frames F] [--spp S]
//                              [--repeats R] [--csv out.csv] [--split-grid n] [--quick] [--gl-speed-only]
//                              [--no-speed]
// --gl-speed-only: only the GL speed rows of item 4 (to compare shader variants quickly); --no-speed: items 1-3.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <string>
#include <vector>

#include "bench/bench_args.h"
#include "renderer/core/parallel.h"
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

/// The indirect light at the pixel centres with exact visibility, sum over the VPLs of Phi T V: T by brute force
/// over grid^2 cone directions, or by the approximation (grid 0).
Image centreImage(const OfflineScene& l, const VplSet& vpls, int size, int grid) {
  const Scene& scene = l.scene();
  std::vector<VslEnd> ends;
  for (const Vpl& v : vpls.vpls)
    ends.push_back({v.position, v.normal, v.geometricNormal, v.incoming, brdfParamsAt(scene, v.material, v.uv)});
  Image image(size, size);
  parallelFor(static_cast<int64_t>(size) * size, 0, [&](int64_t index, int) {
    int x = static_cast<int>(index % size), y = static_cast<int>(index / size);
    glm::vec3 dir = cameraRayDirection(scene.camera, x + 0.5f, y + 0.5f, size, size);
    std::optional<SurfaceHit> hit = l.embree().intersect(scene.camera.position, dir);
    if (!hit || glm::dot(hit->geometricNormal, -dir) <= 0.0f) return;
    VslEnd x1{hit->position, hit->shadingNormal, hit->geometricNormal, -dir,
              brdfParamsAt(scene, hit->material, hit->uv)};
    glm::vec3 sum(0.0f);
    for (std::size_t i = 0; i < ends.size(); ++i) {
      const Vpl& v = vpls.vpls[i];
      if (!l.embree().visible(x1.position, x1.geometricNormal, v.position, v.geometricNormal)) continue;
      // A pure-Lambert pair with an unclipped cone has its closed form (exact, and the approximation's value).
      bool closed = isPureLambert(x1.brdf) && isPureLambert(ends[i].brdf) && vslConeUnclipped(x1, ends[i], v.radius);
      glm::vec3 t = grid > 0 && !closed ? vslTransferNumerical(x1, ends[i], v.radius, grid)
                                        : vslApproxTransfer(x1, ends[i], v.radius);
      sum += v.flux * t;
    }
    image.at(x, y) = sum;
  });
  return image;
}

/// A copy of the scene whose glossy materials (metallic or specular > 0) take the given perceptual roughness.
Scene withGlossyRoughness(Scene scene, float roughness) {
  for (Material& m : scene.materials)
    if (m.metallic > 0.0f || m.specular > 0.0f) m.roughness = roughness;
  return scene;
}

/// Item 3: the GL-vs-CPU comparison of the test, split into its parts.
void errorSplit(const OfflineScene& l, const std::string& label, float radius, int grid) {
  Settings s;
  s.width = s.height = 128;
  s.vplCount = 64;
  s.threads = 2;
  s.components = Components::Indirect;
  s.shadowMapSize = 256;
  s.directLightSamples = 16;
  s.vslRadius = radius;
  s.vslSamples = 4;
  VplSet vpls = generateVpls(l, s);
  PreviewRenderer renderer;
  renderer.render(l.scene(), vpls, s, l.scene().camera);
  Image gl = renderer.readLinear(PreviewOutput::Indirect);
  s.samplesPerPixel = 16;
  Image cpu = renderVpl(l, vpls, Method::Vsl, s).image;
  s.seed = 2;
  Image cpuB = renderVpl(l, vpls, Method::Vsl, s).image;
  Image exact = centreImage(l, vpls, s.width, grid);
  Image approx = centreImage(l, vpls, s.width, 0);
  ImageMetrics total = compareImages(gl, cpu);
  std::printf("%-28s %9.5f %7.4f | %9.5f %7.4f | %9.5f | %9.5f %9.5f | %9.5f\n", label.c_str(), total.relMse,
              total.energyRatioOverall, compareImages(approx, exact).relMse,
              compareImages(approx, exact).energyRatioOverall, compareImages(gl, approx).relMse,
              compareImages(exact, cpu).relMse, compareImages(cpu, cpuB).relMse, compareImages(gl, exact).relMse);
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

/// GL frames of the point VPLs and of the VSLs, alternating (one renderer each, warmed up), so that a change of the
/// machine's load during the measurement touches both alike.
std::pair<Timing, Timing> gatherTimings(const OfflineScene& l, const VplSet& points, const VplSet& vsls,
                                        const Settings& s, int frames) {
  PreviewRenderer pointRenderer, vslRenderer;
  PreviewRenderer* renderers[2] = {&pointRenderer, &vslRenderer};
  const VplSet* sets[2] = {&points, &vsls};
  std::vector<double> ms[2];
  Timing t[2];
  for (int k = 0; k < 2; ++k) {
    renderers[k]->render(l.scene(), *sets[k], s, l.scene().camera);  // compiles, renders the shadow maps
    t[k].cpuMs = 1e30;
  }
  for (int f = 0; f < frames; ++f)
    for (int k = 0; k < 2; ++k) {
      renderers[k]->invalidateFrame();
      double c0 = processCpuSeconds();
      ms[k].push_back(renderers[k]->render(l.scene(), *sets[k], s, l.scene().camera).gatherMs);
      t[k].cpuMs = std::min(t[k].cpuMs, 1e3 * (processCpuSeconds() - c0));
    }
  for (int k = 0; k < 2; ++k) t[k].ms = median(ms[k]);
  return {t[0], t[1]};
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
  int splitGrid = 32;
  bool quick = false, glSpeedOnly = false, noSpeed = false;
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
    } else if (a == "--split-grid") {
      splitGrid = std::max(1, std::atoi(benchOptionValue(argc, argv, i).c_str()));
    } else if (a == "--quick") {
      quick = true;
    } else if (a == "--gl-speed-only") {
      glSpeedOnly = true;
    } else if (a == "--no-speed") {
      noSpeed = true;
    } else {
      std::fprintf(stderr,
                   "usage: %s [--gl auto|egl|osmesa] [--vpls N] [--radius r] [--frames F] [--spp S] "
                   "[--repeats R] [--csv F] [--split-grid n] [--quick] [--gl-speed-only] [--no-speed]\n",
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

    PairError pe;
    ImageMetrics m;
    double noise = 0.0;
    if (!glSpeedOnly) {
      // 1. Approximation error per pair.
      pe = pairError(l, vsls, quick ? 8 : 24);

      // 2. Images at 128^2.
      Settings t = s;
      t.width = t.height = 128;
      PreviewRenderer renderer;
      renderer.render(l.scene(), vsls, t, l.scene().camera);
      Image gl = renderer.readLinear(PreviewOutput::Indirect);
      t.samplesPerPixel = quick ? 2 : 8;
      Image cpuA = renderVpl(l, vsls, Method::Vsl, t).image;
      t.seed = 2;
      Image cpuB = renderVpl(l, vsls, Method::Vsl, t).image;
      m = compareImages(gl, average(cpuA, cpuB));
      noise = compareImages(cpuA, cpuB).relMse;
      std::printf("%-15s %7zu %+7.2f%% %9.2f%% | %11.5f %8.4f %10.5f\n", name.c_str(), pe.pairs, 100.0 * pe.bias,
                  100.0 * pe.meanAbs, m.relMse, m.energyRatioOverall, noise);
    }

    // 4. Speed.
    for (auto [w, h] : noSpeed ? std::vector<std::pair<int, int>>{} : sizes) {
      Settings t = s;
      t.width = w;
      t.height = h;
      t.samplesPerPixel = spp;
      t.clampBound = kInfinity;
      auto [glPoint, glVsl] = gatherTimings(l, points, vsls, t, frames);
      char line[256];
      if (glSpeedOnly) {
        std::snprintf(line, sizeof(line), "%-15s %4dx%-4d %8.0f %8.0f %6.2fx %8.0f %8.0f %6.2fx", name.c_str(), w, h,
                      glPoint.ms, glVsl.ms, glVsl.ms / glPoint.ms, glPoint.cpuMs, glVsl.cpuMs,
                      glVsl.cpuMs / glPoint.cpuMs);
        speedLines.push_back(line);
        continue;
      }
      Timing cpuPoint = cpuTiming(l, points, Method::Vpl, t, repeats);
      Timing cpuVsl = cpuTiming(l, vsls, Method::Vsl, t, repeats);
      std::snprintf(line, sizeof(line),
                    "%-15s %4dx%-4d %8.0f %8.0f %6.2fx %8.0f %8.0f %6.2fx | %8.2f %8.2f %8.2f %8.2f %6.2fx", name.c_str(),
                    w, h, glPoint.ms, glVsl.ms, glVsl.ms / glPoint.ms, glPoint.cpuMs, glVsl.cpuMs,
                    glVsl.cpuMs / glPoint.cpuMs,
                    cpuPoint.ms / 1e3, cpuVsl.ms / 1e3, cpuPoint.cpuMs / 1e3, cpuVsl.cpuMs / 1e3,
                    cpuVsl.cpuMs / cpuPoint.cpuMs);
      speedLines.push_back(line);
      csv << name << ',' << vsls.vpls.size() << ',' << radius << ',' << pe.pairs << ',' << pe.bias << ','
          << pe.meanAbs << ',' << m.relMse << ',' << m.energyRatioOverall << ',' << noise << ',' << w << ',' << h
          << ',' << glPoint.ms << ',' << glVsl.ms << ',' << glPoint.cpuMs << ',' << glVsl.cpuMs << ',' << spp << ','
          << cpuPoint.ms << ',' << cpuVsl.ms << ',' << cpuPoint.cpuMs << ',' << cpuVsl.cpuMs << '\n';
    }
  }
  if (!glSpeedOnly) {
    // 3. The test's comparison, split (the glossy scene also with other roughnesses).
    std::printf("\n128x128, 64 VPLs, CPU 16 spp x 4 samples; brute force %d^2 directions; relMSE (energy)\n", splitGrid);
    std::printf("%-28s %9s %7s | %9s %7s | %9s | %9s %9s | %9s\n", "scene", "GL v CPU", "energy", "approx", "energy",
                "shadowmap", "footprint", "cpu noise", "GL v exact");
    errorSplit(OfflineScene(loadScene(std::string(VPLAB_ASSET_DIR) + "/scenes/cornell-box.gltf")), "cornell-box r=0.05",
               0.05f, splitGrid);
    Scene glossy = loadScene(std::string(VPLAB_ASSET_DIR) + "/scenes/cornell-glossy.gltf");
    errorSplit(OfflineScene(glossy), "cornell-glossy r=0.03", 0.03f, splitGrid);
    for (float roughness : {0.1f, 0.5f}) {
      char label[64];
      std::snprintf(label, sizeof(label), "cornell-glossy rough %.2f", roughness);
      errorSplit(OfflineScene(withGlossyRoughness(glossy, roughness)), label, 0.03f, splitGrid);
    }
  }
  std::printf("\n%-15s %9s %8s %8s %7s %8s %8s %7s | %8s %8s %8s %8s %7s\n", "", "", "GL point", "GL VSL", "ratio",
              "point", "VSL", "ratio", "CPU pt", "CPU VSL", "point", "VSL", "ratio");
  std::printf("%-15s %9s %8s %8s %7s %8s %8s %7s | %8s %8s %8s %8s %7s\n", "scene", "size", "gather", "gather", "(gpu)",
              "cpu ms", "cpu ms", "(cpu)", "wall s", "wall s", "cpu s", "cpu s", "(cpu)");
  for (const std::string& line : speedLines) std::printf("%s\n", line.c_str());
  std::printf("\nwrote %s\n", csvPath.c_str());
  return 0;
}
