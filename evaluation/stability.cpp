#include "evaluation/stability.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "evaluation/svg_chart.h"
#include "renderer/core/atomic_file.h"
#include "renderer/image/heatmap.h"
#include "renderer/image/image_io.h"
#include "renderer/image/metrics.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/vpl/generation_methods.h"
#include "renderer/vpl/vpl_generation.h"

namespace vplab {

namespace {

namespace fs = std::filesystem;

std::string fmt(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

void say(const StabilityConfig& config, const std::string& line) {
  if (config.log) config.log(line);
}

double meanAbsDiff(const Image& a, const Image& b) {
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!isFinite(a.pixels[i]) || !isFinite(b.pixels[i])) continue;
    glm::vec3 d = glm::abs(a.pixels[i] - b.pixels[i]);
    sum += d.r + d.g + d.b;
    n += 3;
  }
  return n ? sum / static_cast<double>(n) : 0.0;
}

// mean |(a1 - a0) - (b1 - b0)|: how much of a method's change the scene's own change does not explain.
double meanExcess(const Image& a0, const Image& a1, const Image& b0, const Image& b1) {
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < a0.size(); ++i) {
    glm::vec3 d = (a1.pixels[i] - a0.pixels[i]) - (b1.pixels[i] - b0.pixels[i]);
    if (!isFinite(d)) continue;
    d = glm::abs(d);
    sum += d.r + d.g + d.b;
    n += 3;
  }
  return n ? sum / static_cast<double>(n) : 0.0;
}

double meanRadiance(const Image& image) {
  double sum = 0.0;
  std::size_t n = 0;
  for (const glm::vec3& p : image.pixels)
    if (isFinite(p)) {
      sum += p.r + p.g + p.b;
      n += 3;
    }
  return n ? sum / static_cast<double>(n) : 0.0;
}

Image absDiffImage(const Image& a, const Image& b) {
  Image d(a.width, a.height);
  for (std::size_t i = 0; i < a.size(); ++i) d.pixels[i] = glm::abs(a.pixels[i] - b.pixels[i]);
  return d;
}

Settings baseSettings(const StabilityConfig& config) {
  Settings s;
  s.width = config.width;
  s.height = config.height;
  s.seed = config.seed;
  s.threads = config.threads;
  s.vplCount = config.vplCount;
  s.samplesPerPixel = config.cpuSpp;
  s.components = Components::Indirect;
  return s;
}

// A flicker method: how its settings differ from the base and which renderer runs it.
struct FlickerMethod {
  std::string name;
  Backend backend;
  Method method;
  std::function<void(Settings&, float diag)> edit;
};

// Every flicker method: the CPU rendering variants of light-traced VPLs, every generation variant of
// renderer/vpl/generation_methods.h on the CPU, and the GL preview's two.
std::vector<FlickerMethod> allFlickerMethods() {
  std::vector<FlickerMethod> all = {
      {"vpl", Backend::Cpu, Method::Vpl, [](Settings&, float) {}},
      {"clamp", Backend::Cpu, Method::Vpl, [](Settings& s, float d) { s.clampBound = 1.0f / (0.01f * d * d); }},
      {"vsl", Backend::Cpu, Method::Vsl, [](Settings& s, float d) { s.vslRadius = 0.03f * d; }},
  };
  for (const GenerationVariant& v : generationVariants()) {
    if (std::string(v.name) == "vpl") continue;
    all.push_back({v.name, Backend::Cpu, Method::Vpl, [&v](Settings& s, float) { applyGenerationVariant(v, s); }});
  }
  // The media methods (meaningful on scenes with participating media).
  all.push_back({"vpl-abc", Backend::Cpu, Method::VplAbc,
                 [](Settings& s, float d) { s.clampBound = 1.0f / (0.01f * d * d); }});
  all.push_back({"vrl", Backend::Cpu, Method::Vrl, [](Settings&, float) {}});
  all.push_back({"vpl-gl", Backend::Gl, Method::Vpl, [](Settings&, float) {}});
  all.push_back({"ssbc-gl", Backend::Gl, Method::Vpl, [](Settings& s, float d) {
                   s.clampBound = 1.0f / (0.01f * d * d);
                   s.ssbcSteps = 2;
                 }});
  return all;
}

std::vector<FlickerMethod> flickerMethods(const StabilityConfig& config) {
  const std::vector<FlickerMethod> all = allFlickerMethods();
  std::vector<std::string> names = config.flickerMethods;
  if (names.empty())
    names = config.quick ? std::vector<std::string>{"vpl", "clamp", "vpl-gl"}
                         : std::vector<std::string>{"vpl", "clamp", "vsl", "reject", "bidirectional", "metropolis",
                                                    "vpl-gl", "ssbc-gl"};
  std::vector<FlickerMethod> out;
  for (const std::string& n : names) {
    auto it = std::find_if(all.begin(), all.end(), [&](const FlickerMethod& m) { return m.name == n; });
    if (it == all.end()) throw std::invalid_argument("unknown flicker method '" + n + "'");
    out.push_back(*it);
  }
  return out;
}

// Per-pixel mean over channels of an error image, sorted descending; the worst 8x8 tile.
void errorConcentration(const Image& err, FailureRow& row) {
  std::vector<double> v;
  v.reserve(err.size());
  double total = 0.0;
  for (const glm::vec3& p : err.pixels)
    if (isFinite(p)) {
      double e = (p.r + p.g + p.b) / 3.0;
      v.push_back(e);
      total += e;
    }
  std::sort(v.begin(), v.end(), std::greater<>());
  std::size_t top = std::max<std::size_t>(1, v.size() / 20);
  double topSum = 0.0;
  for (std::size_t i = 0; i < std::min(top, v.size()); ++i) topSum += v[i];
  row.worstShare = total > 0.0 ? topSum / total : 0.0;
  const int T = 8;
  row.worstTileError = -1.0;
  for (int ty = 0; ty < err.height; ty += T)
    for (int tx = 0; tx < err.width; tx += T) {
      double s = 0.0;
      int n = 0;
      for (int y = ty; y < std::min(ty + T, err.height); ++y)
        for (int x = tx; x < std::min(tx + T, err.width); ++x) {
          glm::vec3 p = err.at(x, y);
          if (!isFinite(p)) continue;
          s += (p.r + p.g + p.b) / 3.0;
          ++n;
        }
      if (n > 0 && s / n > row.worstTileError) {
        row.worstTileError = s / n;
        row.worstTileX = tx;
        row.worstTileY = ty;
      }
    }
  row.worstTileError = std::max(row.worstTileError, 0.0);
}

}  // namespace

const std::vector<std::string>& flickerMethodNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const FlickerMethod& m : allFlickerMethods()) n.push_back(m.name);
    return n;
  }();
  return names;
}

Scene translateLights(const Scene& scene, const glm::vec3& offset) {
  Scene out = scene;
  // Each emissive triangle gets vertices of its own, so a wall that shares a vertex with the light does not stretch.
  for (uint32_t tri : scene.emissiveTriangles) {
    glm::uvec3& t = out.triangles[tri];
    glm::uvec3 fresh;
    for (int k = 0; k < 3; ++k) {
      uint32_t v = t[k];
      fresh[k] = static_cast<uint32_t>(out.positions.size());
      out.positions.push_back(scene.positions[v] + offset);
      out.normals.push_back(scene.normals[v]);
      out.uvs.push_back(v < scene.uvs.size() ? scene.uvs[v] : glm::vec2(0.0f));
    }
    t = fresh;
  }
  for (PunctualLight& l : out.punctualLights) l.position += offset;
  out.finalize();
  return out;
}

std::vector<FlickerRow> measureFlicker(const Scene& scene, const StabilityConfig& config, const std::string& motion,
                                       PreviewBench* gl) {
  if (config.frames < 2) throw std::invalid_argument("stability: at least 2 frames are needed for flicker");
  if (motion != "light" && motion != "camera") throw std::invalid_argument("stability: unknown motion " + motion);
  const float diag = std::max(scene.bounds.diagonal(), 1e-3f);
  const Settings base = baseSettings(config);
  std::vector<FlickerMethod> methods = flickerMethods(config);
  bool haveGl = gl && config.gl && gl->available();

  // The scripted motion: the light slides sideways (x) and down a little, the camera slides along its right axis.
  std::vector<std::unique_ptr<OfflineScene>> frames;
  for (int t = 0; t < config.frames; ++t) {
    Scene s;
    if (motion == "light") {
      s = translateLights(scene, glm::vec3(1.0f, -0.25f, 0.0f) * (config.lightStep * diag * static_cast<float>(t)));
    } else {
      s = scene;
      s.camera.position += s.camera.right() * (config.cameraStep * diag * static_cast<float>(t));
    }
    frames.push_back(std::make_unique<OfflineScene>(std::move(s)));
  }

  // Path-traced frames with one seed: their per-pixel random streams are the same every frame, so what changes is
  // mostly the scene's own change (plus the noise that the motion decorrelates).
  Settings refSettings = base;
  refSettings.samplesPerPixel = config.referenceSpp;
  std::vector<Image> ref;
  for (auto& f : frames) ref.push_back(renderReferenceImage(*f, refSettings).image);
  FlickerRow refRow;
  refRow.motion = motion;
  refRow.method = "reference";
  refRow.vplMode = "-";
  double meanRef = 0.0;
  for (const Image& r : ref) meanRef += meanRadiance(r) / static_cast<double>(ref.size());
  for (int t = 1; t < config.frames; ++t) refRow.perFrame.push_back(meanAbsDiff(ref[t], ref[t - 1]));
  for (double v : refRow.perFrame) refRow.flicker += v / static_cast<double>(refRow.perFrame.size());
  refRow.referenceFlicker = refRow.flicker;
  refRow.meanReference = meanRef;

  std::vector<FlickerRow> rows{refRow};
  for (const FlickerMethod& m : methods) {
    if (m.backend == Backend::Gl && !haveGl) continue;
    for (const char* mode : {"coherent", "reshuffled"}) {
      bool reshuffle = std::string(mode) == "reshuffled";
      std::vector<Image> images;
      for (int t = 0; t < config.frames; ++t) {
        Settings s = base;
        m.edit(s, diag);
        Settings gen = s;
        // Reshuffled: a new VPL seed per frame. Only the VPLs change; the pixel jitter keeps the base seed.
        if (reshuffle) gen.seed = base.seed + 7919u * static_cast<uint32_t>(t + 1);
        VplSet vpls = generateVpls(*frames[t], gen);
        images.push_back(m.backend == Backend::Cpu
                             ? renderCpu(*frames[t], m.method, vpls, s).image
                             : gl->render(frames[t]->scene(), vpls, s, frames[t]->scene().camera).image);
      }
      FlickerRow row;
      row.motion = motion;
      row.method = m.name;
      row.vplMode = mode;
      row.referenceFlicker = refRow.flicker;
      row.meanReference = meanRef;
      double excess = 0.0;
      for (int t = 1; t < config.frames; ++t) {
        row.perFrame.push_back(meanAbsDiff(images[t], images[t - 1]));
        excess += meanExcess(images[t - 1], images[t], ref[t - 1], ref[t]);
      }
      for (double v : row.perFrame) row.flicker += v / static_cast<double>(row.perFrame.size());
      row.excess = excess / static_cast<double>(config.frames - 1);
      say(config, motion + " motion, " + m.name + " " + mode + ": flicker " + fmt(row.flicker) + " (reference " +
                      fmt(refRow.flicker) + ", excess " + fmt(row.excess) + ")");
      // The side-by-side pictures of the point of the test: the change between frames 0 and 1, same colour range.
      if (config.writeImages && m.name == methods.front().name) {
        fs::create_directories(config.outDir + "/images");
        Image d = absDiffImage(images[1], images[0]);
        Image dr = absDiffImage(ref[1], ref[0]);
        HeatmapOptions h;
        h.minValue = 0.0f;
        h.maxValue = static_cast<float>(std::max(1e-6, 4.0 * refRow.flicker + 1e-12));
        h.title = "|I1 - I0| " + m.name + " " + mode;
        writeHeatmap(config.outDir + "/images/flicker-" + motion + "-" + mode + ".png", d, h);
        h.title = "|R1 - R0| path-traced";
        writeHeatmap(config.outDir + "/images/flicker-" + motion + "-reference.png", dr, h);
      }
      rows.push_back(std::move(row));
    }
  }
  return rows;
}

std::vector<FailureRow> failureMaps(const OfflineScene& setup, const StabilityConfig& config, PreviewBench* gl) {
  const float diag = std::max(setup.scene().bounds.diagonal(), 1e-3f);
  const Settings base = baseSettings(config);
  Settings refSettings = base;
  refSettings.samplesPerPixel = config.referenceSpp;
  bool cached = false;
  Image ref =
      cachedReference(setup, sceneStem(setup.scene().sourcePath), refSettings, config.outDir + "/references", &cached)
          .image;
  const float exposure = autoExposure(ref);
  bool haveGl = gl && config.gl && gl->available();
  if (config.writeImages) {
    fs::create_directories(config.outDir + "/images");
    writeImage(config.outDir + "/images/failure-reference.png", ref, exposure);
  }

  std::vector<FailureRow> rows;
  auto record = [&](const std::string& name, const std::string& expected, const Image& image, const Image& against,
                    const std::string& againstName, bool signedMap) {
    FailureRow row;
    row.method = name;
    row.against = againstName;
    row.expected = expected;
    ImageMetrics m = compareImages(image, against);
    row.relMse = m.relMse;
    row.energyRatio = m.energyRatioOverall;
    Image err = relativeErrorImage(image, against);
    errorConcentration(err, row);
    if (config.writeImages) {
      std::string stem = name;
      for (char& c : stem)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '-';
      row.heatmap = "images/failure-" + stem + ".png";
      row.image = "images/failure-" + stem + "-image.png";
      HeatmapOptions h;
      if (signedMap) {
        h.colormap = Colormap::Diverging;
        h.title = "I - R (blue: too dark, red: too bright)";
        writeHeatmap(config.outDir + "/" + row.heatmap, signedDifferenceImage(image, against), h);
      } else {
        h.title = "relative error (I-R)^2/(R^2+0.01)";
        writeHeatmap(config.outDir + "/" + row.heatmap, err, h);
      }
      writeImage(config.outDir + "/" + row.image, image, exposure);
    }
    say(config, "failure map " + name + ": relMSE " + fmt(row.relMse) + ", energy " + fmt(row.energyRatio) +
                    ", worst 5% of pixels hold " + fmt(100.0 * row.worstShare) + "% of the error");
    rows.push_back(std::move(row));
  };

  VplSet plain = generateVpls(setup, base);
  record("vpl (cpu)", "splotches near corners and creases, glossy surfaces",
         renderCpu(setup, Method::Vpl, plain, base).image, ref, "reference", false);
  Settings clamp = base;
  clamp.clampBound = 1.0f / (0.01f * diag * diag);
  record("clamp (cpu)", "darkened corners and cavities, lost glossy inter-reflections",
         renderCpu(setup, Method::Vpl, plain, clamp).image, ref, "reference", true);
  Settings kk = clamp;
  record("vpl-kk (cpu)", "none in bias; noise where the compensation paths go (cost)",
         renderCpu(setup, Method::VplKK, plain, kk).image, ref, "reference", false);
  Settings vsl = base;
  vsl.vslRadius = 0.03f * diag;
  VplSet vslSet = generateVpls(setup, vsl);
  record("vsl (cpu)", "blurred sharp indirect features", renderCpu(setup, Method::Vsl, vslSet, vsl).image, ref,
         "reference", false);
  if (setup.scene().hasMedia()) {
    // The media half (docs/theory.md §17-§20): what the bound removes in fog, and the three remedies.
    record("vpl-abc (cpu)", "the residual's later bounces and the medium-surface residual left out",
           renderCpu(setup, Method::VplAbc, plain, clamp).image, ref, "reference", true);
    record("vrl (cpu)", "noise along thin lines where ray lights pass close to camera rays",
           renderCpu(setup, Method::Vrl, plain, base).image, ref, "reference", false);
    Settings vbl = base;
    vbl.beamPasses = 4;
    record("vbl (cpu)", "blur of the first passes' thick beams", renderCpu(setup, Method::Vbl, plain, vbl).image, ref,
           "reference", true);
  }
  Settings rej = base;
  rej.rejection = true;
  rej.rejectionEpsilon = 0.0f;
  VplSet rejSet = generateVpls(setup, rej);
  record("reject eps=0 (cpu)", "bias where no sample point sees a VPL; local glossy effects",
         renderCpu(setup, Method::Vpl, rejSet, rej).image, ref, "reference", false);
  if (haveGl) {
    Settings ssbc = clamp;
    ssbc.ssbcSteps = 2;
    record("ssbc (gl)", "screen borders, depth discontinuities, occluded or off-screen geometry",
           gl->render(setup.scene(), plain, ssbc, setup.scene().camera).image, ref, "reference", true);
    // Shadow maps against the exact visibility of the CPU pass on the same VPLs: only visibility differs.
    Image exact = renderCpu(setup, Method::Vpl, plain, base).image;
    for (int size : {16, 256}) {
      Settings sm = base;
      sm.shadowMapSize = size;
      record("shadow maps " + std::to_string(size) + " (gl)", "light leaks (red) and acne (blue), resolution",
             gl->render(setup.scene(), plain, sm, setup.scene().camera).image, exact, "cpu exact VPL (same VPLs)",
             true);
    }
  }
  return rows;
}

std::vector<ExtremeRow> runExtremes(const OfflineScene& setup, const StabilityConfig& config, PreviewBench* gl) {
  const float diag = std::max(setup.scene().bounds.diagonal(), 1e-3f);
  Settings base = baseSettings(config);
  base.components = Components::All;
  base.samplesPerPixel = 1;
  const float midB = 1.0f / (0.01f * diag * diag);
  const int largeN = config.quick ? 1024 : 4096;
  bool haveGl = gl && config.gl && gl->available();

  struct Extreme {
    std::string parameter, value, method;
    Backend backend;
    std::function<void(Settings&)> edit;
  };
  std::vector<Extreme> grid;
  auto both = [&](const std::string& p, const std::string& v, const std::string& method,
                  std::function<void(Settings&)> edit) {
    grid.push_back({p, v, method, Backend::Cpu, edit});
    grid.push_back({p, v, method, Backend::Gl, edit});
  };
  both("N", "0", "vpl", [](Settings& s) { s.vplCount = 0; });
  both("N", "1", "vpl", [](Settings& s) { s.vplCount = 1; });
  both("N", std::to_string(largeN), "vpl", [&](Settings& s) {
    s.vplCount = largeN;
    s.shadowMapSize = 32;  // GL: 6 faces per VPL; 32 keeps thousands of cubes within memory
  });
  both("b", "0", "vpl", [](Settings& s) { s.clampBound = 0.0f; });
  both("b", "inf", "vpl", [](Settings& s) { s.clampBound = kInfinity; });
  grid.push_back({"b", "0", "vpl-kk", Backend::Cpu, [](Settings& s) { s.clampBound = 0.0f; }});
  grid.push_back({"b", "inf", "vpl-kk", Backend::Cpu, [](Settings& s) { s.clampBound = kInfinity; }});
  if (setup.scene().hasMedia()) {
    grid.push_back({"b", "0", "vpl-abc", Backend::Cpu, [](Settings& s) { s.clampBound = 0.0f; }});
    grid.push_back({"N", "1", "vrl", Backend::Cpu, [](Settings& s) { s.vplCount = 1; }});
  }
  both("r", "0", "vsl", [](Settings& s) { s.vslRadius = 0.0f; });
  both("r", fmt(10.0 * diag), "vsl", [&](Settings& s) { s.vslRadius = 10.0f * diag; });
  for (float e : {0.0f, 1.0f})
    both("epsilon", fmt(e), "reject", [e](Settings& s) {
      s.rejection = true;
      s.rejectionEpsilon = e;
    });
  for (int k : {1, 8})
    grid.push_back({"k", std::to_string(k), "vpl", Backend::Gl, [k](Settings& s) { s.interleave = k; }});
  for (int size : {16, 2048})
    grid.push_back({"shadow map", std::to_string(size), "vpl", Backend::Gl, [size](Settings& s) {
                      s.shadowMapSize = size;
                      if (size > 256) {
                        // Full-size cubes for a handful of casters only: 6 x 1024^2 texels each.
                        s.vplCount = 4;
                        s.directLightSamples = 1;
                      }
                    }});
  for (int steps : {0, 2})
    for (const char* b : {"mid", "0"})
      grid.push_back({"ssbc",
                      std::to_string(steps) + " (b=" + std::string(std::string(b) == "mid" ? fmt(midB) : "0") + ")",
                      "ssbc", Backend::Gl, [steps, b, midB](Settings& s) {
                        s.ssbcSteps = steps;
                        s.clampBound = std::string(b) == "mid" ? midB : 0.0f;
                      }});

  std::vector<ExtremeRow> rows;
  for (const Extreme& e : grid) {
    if (e.backend == Backend::Gl && !haveGl) continue;
    Settings s = base;
    e.edit(s);
    VplSet vpls = generateVpls(setup, s);
    MeasuredImage m;
    if (e.backend == Backend::Cpu) {
      Method method = Method::Vpl;
      if (!parseMethod(e.method, method)) method = Method::Vpl;
      m = renderCpu(setup, method, vpls, s);
    } else {
      m = gl->render(setup.scene(), vpls, s, setup.scene().camera);
    }
    ExtremeRow row{e.parameter,          e.value, e.method, e.backend, m.totalMs(), countBadPixels(m.image),
                   meanRadiance(m.image)};
    say(config, "extreme " + e.parameter + " = " + e.value + ", " + e.method + " (" + toString(e.backend) +
                    "): " + std::to_string(row.bad.nonFinite) + " non-finite, " + std::to_string(row.bad.negative) +
                    " negative, " + fmt(row.timeMs) + " ms");
    rows.push_back(std::move(row));
  }
  return rows;
}

StabilityOutcome runStability(const std::string& scenePath, const StabilityConfig& config) {
  fs::create_directories(config.outDir);
  StabilityOutcome out;
  Scene scene = loadSweepScene(config.loadScene, scenePath);
  const std::string name = sceneStem(scenePath);
  PreviewBench gl(config.glBackend);
  if (config.gl && !gl.available()) {
    out.glNote = "GL parts skipped: " + gl.error();
    say(config, out.glNote);
  }
  PreviewBench* glp = config.gl ? &gl : nullptr;

  for (const char* motion : {"light", "camera"}) {
    auto rows = measureFlicker(scene, config, motion, glp);
    out.flicker.insert(out.flicker.end(), rows.begin(), rows.end());
  }
  OfflineScene setup(scene);
  out.failures = failureMaps(setup, config, glp);
  out.extremes = runExtremes(setup, config, glp);
  for (const ExtremeRow& r : out.extremes) out.extremesClean = out.extremesClean && r.bad.total() == 0;

  // CSVs, one row per measurement.
  {
    std::ostringstream f;
    f << "scene,motion,method,vpls,frames,flicker,reference_flicker,excess,mean_reference\n";
    for (const FlickerRow& r : out.flicker)
      f << name << "," << r.motion << "," << r.method << "," << r.vplMode << "," << config.frames << ","
        << fmt(r.flicker) << "," << fmt(r.referenceFlicker) << "," << fmt(r.excess) << "," << fmt(r.meanReference)
        << "\n";
    writeFileAtomically(config.outDir + "/flicker.csv", f.str());
  }
  {
    std::ostringstream f;
    f << "scene,map,against,relmse,energy_ratio,worst5_share,worst_tile_x,worst_tile_y,worst_tile_error,heatmap\n";
    for (const FailureRow& r : out.failures)
      f << name << ",\"" << r.method << "\",\"" << r.against << "\"," << fmt(r.relMse) << "," << fmt(r.energyRatio)
        << "," << fmt(r.worstShare) << "," << r.worstTileX << "," << r.worstTileY << "," << fmt(r.worstTileError) << ","
        << r.heatmap << "\n";
    writeFileAtomically(config.outDir + "/failures.csv", f.str());
  }
  {
    std::ostringstream f;
    f << "scene,parameter,value,method,backend,time_ms,nonfinite,negative,mean_radiance\n";
    for (const ExtremeRow& r : out.extremes)
      f << name << "," << r.parameter << ",\"" << r.value << "\"," << r.method << "," << toString(r.backend) << ","
        << fmt(r.timeMs) << "," << r.bad.nonFinite << "," << r.bad.negative << "," << fmt(r.meanRadiance) << "\n";
    writeFileAtomically(config.outDir + "/extremes.csv", f.str());
  }

  // Per-frame flicker charts, one per motion.
  fs::create_directories(config.outDir + "/charts");
  std::vector<std::string> charts;
  for (const char* motion : {"light", "camera"}) {
    ChartSpec c;
    c.title = name + ": frame-to-frame change under a small " + std::string(motion) + " motion";
    c.xLabel = "frame t";
    c.yLabel = "mean |I_t - I_(t-1)|";
    c.logY = true;
    for (const FlickerRow& r : out.flicker) {
      if (r.motion != motion) continue;
      ChartSeries s;
      s.name = r.method == "reference" ? "path-traced" : r.method + " " + r.vplMode;
      for (std::size_t t = 0; t < r.perFrame.size(); ++t)
        s.points.push_back({static_cast<double>(t + 1), r.perFrame[t]});
      c.series.push_back(std::move(s));
    }
    std::string file = "charts/" + name + "-flicker-" + motion + ".svg";
    writeSvgChart(config.outDir + "/" + file, c);
    charts.push_back(file);
  }

  std::ostringstream md;
  md << "# vplab stability report: " << name << "\n\n"
     << config.width << "x" << config.height << ", N = " << config.vplCount << " VPLs, " << config.frames
     << " frames, references at " << config.referenceSpp << " spp. Flicker and failure maps compare the indirect "
     << "component; extremes check full images.\n\n## 1. Flicker\n\n"
     << "Mean |I_t - I_(t-1)| per pixel and channel over a scripted motion (light: " << config.lightStep
     << " x the scene diagonal per frame; camera: " << config.cameraStep
     << " sideways). *reference* is the path-traced frames' own change; *excess* = mean |dI - dR| is change "
        "the scene does not explain. Coherent VPLs use one seed (QMC light paths move a little with the light); "
        "reshuffled VPLs take a new seed each frame.\n\n"
     << "| motion | method | VPLs | flicker | reference | flicker / reference | excess "
        "|\n|---|---|---|---:|---:|---:|---:|\n";
  for (const FlickerRow& r : out.flicker)
    md << "| " << r.motion << " | " << r.method << " | " << r.vplMode << " | " << fmt(r.flicker) << " | "
       << fmt(r.referenceFlicker) << " | " << fmt(r.referenceFlicker > 0 ? r.flicker / r.referenceFlicker : 0.0)
       << " | " << fmt(r.excess) << " |\n";
  md << "\n";
  for (const std::string& c : charts) md << "![flicker](" << c << ")\n\n";
  if (config.writeImages) {
    md << "Change between frames 0 and 1 (same colour range):\n\n| motion | path-traced | coherent VPLs | reshuffled "
          "VPLs |\n|---|---|---|---|\n";
    for (const char* motion : {"light", "camera"})
      md << "| " << motion << " | ![](images/flicker-" << motion << "-reference.png) | ![](images/flicker-" << motion
         << "-coherent.png) | ![](images/flicker-" << motion << "-reshuffled.png) |\n";
    md << "\n";
  }
  md << "## 2. Failure maps\n\nWorst 5%: the share of the summed per-pixel relative error held by the 5% worst "
        "pixels (0.05 = evenly spread). Worst tile: the 8x8 block with the largest mean error (its top-left pixel).\n\n"
        "| map | against | expected failure | relMSE | energy | worst 5% | worst tile | heatmap | image |\n"
        "|---|---|---|---:|---:|---:|---|---|---|\n";
  for (const FailureRow& r : out.failures)
    md << "| " << r.method << " | " << r.against << " | " << r.expected << " | " << fmt(r.relMse) << " | "
       << fmt(r.energyRatio) << " | " << fmt(r.worstShare) << " | (" << r.worstTileX << ", " << r.worstTileY << ") "
       << fmt(r.worstTileError) << " | " << (r.heatmap.empty() ? "-" : "![](" + r.heatmap + ")") << " | "
       << (r.image.empty() ? "-" : "![](" + r.image + ")") << " |\n";
  md << "\n## 3. Extremes\n\nEvery image must be free of non-finite and negative pixels.\n\n"
        "| parameter | value | method | backend | time [ms] | non-finite | negative | mean radiance |\n"
        "|---|---|---|---|---:|---:|---:|---:|\n";
  for (const ExtremeRow& r : out.extremes)
    md << "| " << r.parameter << " | " << r.value << " | " << r.method << " | " << toString(r.backend) << " | "
       << fmt(r.timeMs) << " | " << r.bad.nonFinite << " | " << r.bad.negative << " | " << fmt(r.meanRadiance)
       << " |\n";
  md << "\n**" << (out.extremesClean ? "All extremes clean." : "Some extremes produced bad pixels.") << "**\n";
  if (!out.glNote.empty()) md << "\n" << out.glNote << "\n";
  out.reportPath = config.outDir + "/stability.md";
  writeFileAtomically(out.reportPath, md.str());
  return out;
}

}  // namespace vplab
