// CPU many-light benchmark: exact VPL rendering (vpl, vpl-kk, vsl) swept over the VPL count N and the clamp bound b
// on cornell-box and two-rooms; time, relMSE against the path-traced reference (indirect component) and VPL shadow
// rays/s, next to the raw occlusion throughput of EmbreeScene::occludedBatch on the same machine and rays.
//   vplab_bench_vpl_bench [--size N] [--threads T] [--ref-spp N] [--csv out.csv] [--quick]
// Prints a table; --csv writes one row per configuration.

#include "bench/bench_args.h"
#include "renderer/core/parallel.h"
#include "renderer/image/metrics.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/offline/path_tracer.h"
#include "renderer/offline/progressive.h"
#include "renderer/offline/vpl_renderer.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/vpl/vpl_generation.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

using namespace vplab;

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

/// Shadow rays from the camera-visible points of the image (pixel centres) to every VPL: the rays the VPL sum
/// traces, so the raw rate is measured on the same distribution.
std::vector<ShadowRay> shadowRaysOfImage(const Scene& scene, const EmbreeScene& embree, const VplSet& vpls,
                                         int width, int height) {
  std::vector<ShadowRay> rays;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      glm::vec3 dir = cameraRayDirection(scene.camera, x + 0.5f, y + 0.5f, width, height);
      auto hit = embree.intersect(scene.camera.position, dir);
      if (!hit) continue;
      for (const Vpl& v : vpls.vpls)
        rays.push_back(embree.shadowRayBetween(hit->position, hit->geometricNormal, v.position, v.geometricNormal));
    }
  return rays;
}

/// Raw occludedBatch throughput over `rays`, in batches of 64 (what the renderer uses) on all threads.
double rawOcclusionRate(const EmbreeScene& embree, const std::vector<ShadowRay>& rays, int threads) {
  const int64_t batch = 64;
  const int64_t items = (static_cast<int64_t>(rays.size()) + batch - 1) / batch;
  std::vector<uint8_t> out(rays.size());
  double best = 0.0;
  for (int rep = 0; rep < 3; ++rep) {
    double t0 = now();
    parallelFor(items, threads, [&](int64_t i, int) {
      std::size_t begin = static_cast<std::size_t>(i * batch);
      std::size_t count = std::min<std::size_t>(batch, rays.size() - begin);
      embree.occludedBatch(rays.data() + begin, out.data() + begin, count);
    });
    best = std::max(best, static_cast<double>(rays.size()) / (now() - t0));
  }
  return best;
}

struct Row {
  std::string scene, method;
  int vpls = 0;
  float clamp = 0.0f, radius = 0.0f;
  double genSeconds = 0.0, renderSeconds = 0.0, relMse = 0.0, energy = 0.0, clampRemoved = 0.0;
  double raysPerSecond = 0.0, rawRaysPerSecond = 0.0;
  uint64_t accepted = 0;
};

}  // namespace

int main(int argc, char** argv) {
  int size = 64, threads = 0, refSpp = 512;
  bool quick = false;
  std::string csv = "vpl_bench.csv";
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto next = [&] { return benchOptionValue(argc, argv, i); };
    if (a == "--size") size = std::atoi(next().c_str());
    else if (a == "--threads") threads = std::atoi(next().c_str());
    else if (a == "--ref-spp") refSpp = std::atoi(next().c_str());
    else if (a == "--csv") csv = next();
    else if (a == "--quick") quick = true;
    else {
      std::fprintf(stderr, "usage: %s [--size N] [--threads T] [--ref-spp N] [--csv out.csv] [--quick]\n", argv[0]);
      return 2;
    }
  }
  const std::vector<int> counts = quick ? std::vector<int>{64, 256} : std::vector<int>{64, 256, 1024, 4096};
  const std::vector<float> bounds = {kInfinity, 10.0f, 1.0f};
  const float vslRadius = 0.02f;

  std::vector<Row> rows;
  std::printf("%-12s %-7s %5s %6s %5s %8s %8s %10s %7s %7s %9s %9s %6s\n", "scene", "method", "N", "b", "r",
              "gen s", "render s", "relMSE", "energy", "clamp%", "Mray/s", "raw Mr/s", "ratio");
  for (const char* name : {"cornell-box", "two-rooms"}) {
    Scene scene = loadScene(std::string(VPLAB_ASSET_DIR) + "/scenes/" + name + ".gltf");
    OfflineScene offline(scene);
    Settings base;
    base.width = base.height = size;
    base.threads = threads;
    base.samplesPerPixel = 1;
    base.components = Components::Indirect;
    // VPL bounce k is light reflected k + 1 times at the camera: match the reference's path length, so relMSE
    // measures the methods and not a truncation.
    base.vplMaxBounces = base.maxDepth - 1;
    Settings refSettings = base;
    refSettings.samplesPerPixel = refSpp;
    Image reference = renderReference(offline, refSettings).image;

    for (int n : counts) {
      Settings s = base;
      s.vplCount = n;
      VplSet vpls = generateVpls(offline, s);
      const EmbreeScene& embree = offline.embree();
      double raw = rawOcclusionRate(embree, shadowRaysOfImage(scene, embree, vpls, size, size), threads);
      for (Method method : {Method::Vpl, Method::VplKK, Method::Vsl}) {
        for (float b : bounds) {
          // KK without a bound is plain VPL; VSL ignores the bound.
          if (method == Method::VplKK && std::isinf(b)) continue;
          if (method == Method::Vsl && !std::isinf(b)) continue;
          Settings rs = s;
          rs.clampBound = b;
          rs.vslRadius = method == Method::Vsl ? vslRadius : 0.0f;
          VplRenderResult r = renderVpl(offline, vpls, method, rs);
          ImageMetrics m = compareImages(r.image, reference);
          Row row;
          row.scene = name;
          row.method = toString(method);
          row.vpls = n;
          row.clamp = b;
          row.radius = rs.vslRadius;
          row.genSeconds = vpls.stats.generationSeconds;
          row.renderSeconds = r.seconds;
          row.relMse = m.relMse;
          row.energy = m.energyRatioOverall;
          row.clampRemoved = r.clampEnergyRemoved;
          row.raysPerSecond = r.seconds > 0.0 ? static_cast<double>(r.shadowRays) / r.seconds : 0.0;
          row.rawRaysPerSecond = raw;
          row.accepted = vpls.stats.accepted;
          rows.push_back(row);
          std::printf("%-12s %-7s %5d %6g %5g %8.3f %8.3f %10.5f %7.3f %7.2f %9.2f %9.2f %6.2f\n", name,
                      row.method.c_str(), n, b, row.radius, row.genSeconds, row.renderSeconds, row.relMse,
                      row.energy, 100.0 * row.clampRemoved, 1e-6 * row.raysPerSecond, 1e-6 * raw,
                      raw > 0.0 ? row.raysPerSecond / raw : 0.0);
          std::fflush(stdout);
        }
      }
    }
  }

  if (FILE* f = std::fopen(csv.c_str(), "w")) {
    std::fprintf(f, "scene,method,vpls_requested,vpls_accepted,clamp_b,vsl_radius,generation_s,render_s,relmse,"
                    "energy_ratio,clamp_energy_removed,shadow_rays_per_s,raw_occlusion_rays_per_s\n");
    for (const Row& r : rows)
      std::fprintf(f, "%s,%s,%d,%llu,%g,%g,%.4f,%.4f,%.6g,%.5f,%.5f,%.4g,%.4g\n", r.scene.c_str(), r.method.c_str(),
                   r.vpls, static_cast<unsigned long long>(r.accepted), r.clamp, r.radius, r.genSeconds,
                   r.renderSeconds, r.relMse, r.energy, r.clampRemoved, r.raysPerSecond, r.rawRaysPerSecond);
    std::fclose(f);
    std::printf("wrote %s\n", csv.c_str());
  } else {
    std::fprintf(stderr, "cannot write %s\n", csv.c_str());
    return 1;
  }
  return 0;
}
