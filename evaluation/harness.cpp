#include "evaluation/harness.h"

#include "renderer/offline/render_methods.h"

#include <glad/gl.h>

#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>

#include "renderer/core/sampling.h"
#include "renderer/image/image_io.h"
#include "renderer/image/metrics.h"
#include "renderer/offline/path_tracer.h"
#include "renderer/offline/vpl_renderer.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/vpl/vpl_generation.h"

namespace vplab {

const char* toString(Backend backend) {
  return backend == Backend::Cpu ? "cpu" : "gl";
}

Scene loadSweepScene(const SceneLoader& loader, const std::string& path) {
  return loader ? loader(path) : loadScene(path);
}

namespace {

/// A hash of what the reference of a scene depends on: geometry, materials (and their textures' texels), lights and
/// camera. Staging, a lights sidecar or an edit of the file change it, so a cached reference is never reused for a
/// scene that differs from the one it was rendered from.
uint64_t sceneFingerprint(const Scene& scene) {
  uint64_t h = 0x7363656e65ull;
  auto add = [&h](const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; i += 8) {
      uint64_t word = 0;
      std::memcpy(&word, p + i, std::min<std::size_t>(8, bytes - i));
      h = hashKey(h, word);
    }
  };
  auto addVector = [&add](const auto& v) { add(v.data(), v.size() * sizeof(v[0])); };
  addVector(scene.positions);
  addVector(scene.normals);
  addVector(scene.uvs);
  addVector(scene.triangles);
  addVector(scene.triangleMaterials);
  for (const Material& m : scene.materials) {
    const float values[] = {m.baseColor.r, m.baseColor.g, m.baseColor.b, m.metallic, m.roughness, m.specular,
                            m.emission.r,  m.emission.g,  m.emission.b};
    const int textures[] = {m.baseColorTexture, m.emissiveTexture};
    add(values, sizeof values);
    add(textures, sizeof textures);
    add(&m.emissiveUvTransform, sizeof m.emissiveUvTransform);
  }
  for (const Texture& t : scene.textures) addVector(t.texels);
  for (const PunctualLight& l : scene.punctualLights) {
    const float values[] = {l.position.x,  l.position.y,  l.position.z,  l.direction.x,    l.direction.y,
                            l.direction.z, l.intensity.r, l.intensity.g, l.intensity.b, l.innerConeAngle,
                            l.outerConeAngle};
    const int type = static_cast<int>(l.type);
    add(values, sizeof values);
    add(&type, sizeof type);
  }
  const Camera& c = scene.camera;
  const float camera[] = {c.position.x, c.position.y, c.position.z, c.forward.x, c.forward.y, c.forward.z,
                          c.up.x,       c.up.y,       c.up.z,       c.yfov};
  add(camera, sizeof camera);
  return h;
}

std::string fingerprintText(uint64_t fingerprint) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(fingerprint));
  return text;
}

}  // namespace

MeasuredImage renderCpu(const OfflineScene& offline, Method method, const VplSet& vpls, const Settings& settings) {
  assert(method != Method::Reference);
  MeasuredImage m;
  VplRenderResult r = renderMethod(method).render(offline, vpls, settings, nullptr, {});
  m.image = std::move(r.image);
  m.generationMs = 1000.0 * vpls.stats.generationSeconds;
  m.renderMs = 1000.0 * r.seconds;
  m.vplStats = vpls.stats;
  return m;
}

EqualTimeRender renderForSeconds(const OfflineScene& offline, Method method, const Settings& settings, double seconds) {
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  EqualTimeRender r;
  r.image = Image(settings.width, settings.height);
  double removed = 0.0;
  do {
    Settings pass = settings;
    pass.seed = settings.seed + static_cast<uint32_t>(r.passes);
    pass.samplesPerPixel = 1;
    const VplSet set = renderMethod(method).usesVpls ? generateVpls(offline, pass) : VplSet{};
    const VplRenderResult one = renderMethod(method).render(offline, set, pass, nullptr, {});
    for (std::size_t p = 0; p < r.image.pixels.size(); ++p) r.image.pixels[p] += one.image.pixels[p];
    removed += one.clampEnergyRemoved;
    ++r.passes;
  } while (elapsed() < seconds);
  for (glm::vec3& p : r.image.pixels) p /= static_cast<float>(r.passes);
  r.clampEnergyRemoved = removed / r.passes;
  r.seconds = elapsed();
  return r;
}

MeasuredImage renderReferenceImage(const OfflineScene& offline, const Settings& settings) {
  MeasuredImage m;
  ProgressiveResult r = renderReference(offline, settings);
  m.image = std::move(r.image);
  m.renderMs = 1000.0 * r.seconds;
  return m;
}

PreviewBench::PreviewBench(GlBackend backend) : backend_(backend) {}
PreviewBench::~PreviewBench() {
  // The renderer's GL objects must go while their context is still current.
  if (context_) context_->makeCurrent();
  renderer_.reset();
  context_.reset();
}

bool PreviewBench::available() {
  if (!tried_) {
    tried_ = true;
    try {
      context_ = std::make_unique<HeadlessGlContext>(backend_);
      renderer_ = std::make_unique<PreviewRenderer>();
    } catch (const std::exception& e) {
      error_ = e.what();
      renderer_.reset();
      context_.reset();
    }
  }
  return renderer_ != nullptr;
}

std::string PreviewBench::description() {
  return available() ? context_->description() : "no GL: " + error_;
}

MeasuredImage PreviewBench::render(const Scene& scene, const VplSet& vpls, const Settings& settings,
                                   const Camera& camera) {
  assert(settings.components != Components::Direct);
  if (!available()) throw GlError("GL preview unavailable: " + error_);
  context_->makeCurrent();
  MeasuredImage m;
  m.generationMs = 1000.0 * vpls.stats.generationSeconds;
  m.vplStats = vpls.stats;
  Settings frame = settings;
  // The direct light is not compared in Indirect mode: one shadow-mapped light sample keeps its passes (which the
  // gather needs to run at all) from dominating the time of the VPL work being measured.
  if (settings.components == Components::Indirect) frame.directLightSamples = 1;
  if (!warmedUp_) {
    // The first frame of a context compiles (and in software GL, JIT-compiles) every shader: not part of any method.
    renderer_->render(scene, vpls, frame, camera);
    glFinish();
    warmedUp_ = true;
  }
  // A frame from scratch: the scene and the VPLs are invalidated so every pass, VPL shadow maps included, runs.
  // The faster of two such frames: the first one after a change of size or VPL count also reallocates textures.
  m.renderMs = std::numeric_limits<double>::infinity();
  for (int repeat = 0; repeat < 2; ++repeat) {
    renderer_->invalidateScene();
    renderer_->invalidateVpls();
    auto start = std::chrono::steady_clock::now();
    renderer_->render(scene, vpls, frame, camera);
    glFinish();
    m.renderMs = std::min(m.renderMs,
                          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  m.image = readPreviewComponents(*renderer_, settings);
  return m;
}

Image readPreviewComponents(PreviewRenderer& renderer, const Settings& settings) {
  if (settings.components == Components::All) return renderer.readLinear(PreviewOutput::Final);
  Image indirect = renderer.readLinear(PreviewOutput::Indirect);
  if (settings.ssbcSteps > 0 && std::isfinite(settings.clampBound)) {
    Image residual = renderer.readLinear(PreviewOutput::Residual);
    for (std::size_t i = 0; i < indirect.size(); ++i) indirect.pixels[i] += residual.pixels[i];
  }
  if (settings.components == Components::Indirect) return indirect;
  Image direct = renderer.readLinear(PreviewOutput::Final);
  for (std::size_t i = 0; i < direct.size(); ++i) direct.pixels[i] -= indirect.pixels[i];
  return direct;
}

std::string sceneStem(const std::string& path) {
  return std::filesystem::path(path).stem().string();
}

MeasuredImage cachedReference(const OfflineScene& setup, const std::string& sceneName, const Settings& settings,
                              const std::string& cacheDir, bool* cached) {
  std::string file;
  if (!cacheDir.empty()) {
    std::filesystem::create_directories(cacheDir);
    file = cacheDir + "/ref-" + sceneName + "-" + std::to_string(settings.width) + "x" +
           std::to_string(settings.height) + "-" + std::to_string(settings.samplesPerPixel) + "spp-" +
           toString(settings.components) + "-d" + std::to_string(settings.maxDepth) + "-s" +
           std::to_string(settings.seed) + "-" + fingerprintText(sceneFingerprint(setup.scene())) + ".exr";
    if (std::filesystem::exists(file)) {
      // A file that does not read back as an image of the right size (cut, empty, replaced by hand) is rendered
      // again and replaced, never trusted and never a reason to fail every later run.
      try {
        MeasuredImage m;
        m.image = readImage(file);
        if (m.image.width == settings.width && m.image.height == settings.height) {
          if (cached) *cached = true;
          return m;
        }
      } catch (const ImageIoError&) {
      }
    }
  }
  if (cached) *cached = false;
  MeasuredImage m = renderReferenceImage(setup, settings);
  if (!file.empty()) {
    ImageInfo info = {{"components", toString(settings.components)},
                      {"method", toString(Method::Reference)},
                      {"spp", std::to_string(settings.samplesPerPixel)}};
    writeImage(file, m.image, 0.0f, info);
    // Cached only when it reads back bit for bit: a later run trusts this file instead of rendering.
    Image back = readImage(file);
    if (back.width != m.image.width || back.height != m.image.height ||
        std::memcmp(back.pixels.data(), m.image.pixels.data(), m.image.size() * sizeof(glm::vec3)) != 0) {
      std::filesystem::remove(file);
      throw ImageIoError(file + ": the cached reference does not read back as written; removed");
    }
  }
  return m;
}

float autoExposure(const Image& image) {
  double sum = 0.0;
  std::size_t n = 0;
  for (const glm::vec3& p : image.pixels)
    if (isFinite(p)) {
      sum += luminance(p);
      ++n;
    }
  if (n == 0 || sum <= 0.0) return 0.0f;
  double stops = std::log2(0.18 / (sum / static_cast<double>(n)));
  return static_cast<float>(std::clamp(stops, -12.0, 12.0));
}

BadPixels countBadPixels(const Image& image) {
  BadPixels b;
  for (const glm::vec3& p : image.pixels) {
    if (!isFinite(p))
      ++b.nonFinite;
    else if (p.r < 0.0f || p.g < 0.0f || p.b < 0.0f)
      ++b.negative;
  }
  return b;
}

}  // namespace vplab
