#include "renderer/gl/preview_renderer.h"

#include <glad/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "renderer/core/sampling.h"
#include "renderer/gl/texture_units.h"

namespace vplab {

namespace {

/// A colour texture with its own framebuffer.
struct Target {
  GlTexture texture;
  GlFramebuffer framebuffer;
  Target(int w, int h, int levels = 1) : texture(w, h, TextureFormat::Rgba32F, levels) {
    framebuffer.attachColor(0, texture);
    framebuffer.finalize(1);
  }
};

// std140 layouts of the light tables of shaders/preview/direct.frag.glsl and common/gather.glsl.
struct DirectLightGpu {
  glm::vec4 position, axis, weight, shadow, centre;
};

// Texels per side of a light's cube-map face: a few lights, not one map per sample, so they can be sharp (a texel spans
// 0.1 degrees: no stair-steps at contact shadows).
constexpr int kLightShadowFaceSize = 1024;
// Texels per side of a directional light's orthographic map over the scene's bounding sphere.
constexpr int kDirectionalShadowSize = 2048;
// VPLs a gather draw evaluates per pixel at most (per interleaving subset): the unit a frame budget can stop after.
constexpr int kGatherVplsPerDraw = 64;
struct VplGpu {
  glm::vec4 position, normal, incoming, flux, baseColor, geoNormal, lambertPower;
};

// The light tables (VPLs for the gather, light samples for the direct pass) are read from uniform blocks, which
// llvmpipe reads faster than storage buffers. A block holds what GL_MAX_UNIFORM_BLOCK_SIZE allows, at most 1024
// elements so that the shader's array stays small where a driver allows very large blocks; a longer table is drawn in
// ranges, each bound from an element whose byte offset is a multiple of GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT.
UniformTableLayout uniformTableLayout(std::size_t elementBytes) {
  UniformTableLayout layout;
  layout.elementBytes = elementBytes;
  GLint blockBytes = 0, offsetAlignment = 1;
  glGetIntegerv(GL_MAX_UNIFORM_BLOCK_SIZE, &blockBytes);
  glGetIntegerv(GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT, &offsetAlignment);
  const GLint bytes = static_cast<GLint>(elementBytes);
  layout.capacity = std::clamp(static_cast<int>(blockBytes / bytes), 1, 1024);
  // Element i starts at byte i * elementBytes, a multiple of the alignment when i is a multiple of this.
  layout.alignment = std::max(1, offsetAlignment / std::gcd(offsetAlignment, bytes));
  if (layout.alignment > layout.capacity) throw GlError("uniform buffer offset alignment larger than a block");
  return layout;
}

std::string uniformTableDefine(const char* name, std::size_t elementBytes) {
  return std::string(name) + " " + std::to_string(uniformTableLayout(elementBytes).capacity);
}

// Calls visit(base, begin, end) for consecutive ranges [begin, end) that cover [first, last), each of which fits one
// uniform block bound from element base <= begin on.
template <class F>
void forEachUniformRange(const UniformTableLayout& layout, int first, int last, F&& visit) {
  for (int begin = first; begin < last;) {
    int base = begin / layout.alignment * layout.alignment;
    int end = std::min(last, base + layout.capacity);
    visit(base, begin, end);
    begin = end;
  }
}

// A light table drawn in one chunk (the direct lights: their maps are layers of one texture).
struct SingleChunk {
  int count;
  int chunkCount() const { return count > 0 ? 1 : 0; }
  int chunkBegin(int) const { return 0; }
  int chunkEnd(int) const { return count; }
};

// Interleaved sampling: subset s of a k x k pattern takes the lights i = s, s + k^2, ...; this is how far the first of
// them lies after `rangeBegin`, the first light of a draw's range (common/interleaved.glsl).
int subsetOffset(int rangeBegin, int subset, int k) {
  int k2 = k * k;
  return ((subset - rangeBegin % k2) + k2) % k2;
}

bool sameCamera(const Camera& a, const Camera& b) {
  return a.position == b.position && a.forward == b.forward && a.up == b.up && a.yfov == b.yfov && a.znear == b.znear &&
         a.zfar == b.zfar;
}

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// Runs `body` between a GL_TIME_ELAPSED query's begin and end and returns the GPU milliseconds; wallMs receives the
// CPU time until the result was available (resultMs() waits for the GPU).
template <typename F>
double timed(GlTimerQuery& timer, double& wallMs, F&& body) {
  auto start = std::chrono::steady_clock::now();
  timer.begin();
  body();
  timer.end();
  double gpu = timer.resultMs();
  wallMs = msSince(start);
  // resultMs() waits for the GPU, so the GPU time can never exceed the wall time around it. llvmpipe answers the
  // first query of a context with the absolute clock (hours); such a value is replaced by the wall time.
  return gpu <= wallMs ? gpu : wallMs;
}

}  // namespace

struct PreviewRenderer::Targets {
  int width, height;
  GlTexture gPosition, gNormal, gBaseColor, gEmission, gGeoNormal, gMergeKey, gDepth;
  GlFramebuffer gbuffer;
  // Whether the mips of gPosition and gNormal (compensation only) were made from the current G-buffer.
  bool gbufferMipsCurrent = false;
  Target direct, indirect, i0, r1, r2, linear, display;
  // Row sums of the separable de-interleave (deinterleave.frag.glsl), accepted count in w.
  Target rows;
  // Per mip texel of the G-buffer: x2 with the packed unit normal, and dA, of a compensation tap
  // (ssbc_taps.frag.glsl), one framebuffer per level; I dA per mip texel of a step's input (ssbc_radiance.frag.glsl).
  GlTexture ssbcTaps, ssbcArea, ssbcRadiance;
  std::vector<GlFramebuffer> ssbcTapLevels, ssbcRadianceLevels;
  // The coarse rings of a compensation step at every 4th pixel (ssbc.frag.glsl with SSBC_COARSE_PASS), and their
  // far rings alone (second attachment of ssbcCoarse.framebuffer).
  Target ssbcCoarse;
  GlTexture ssbcCoarseFar;
  // Per coarse block: whether every fine-ring tap of its pixels is coplanar with them (ssbc_flat.frag.glsl), from
  // per-row summaries of the blocks' windows (plane, and state: found, all on it, tolerance).
  Target ssbcFlat;
  GlTexture ssbcFlatRowPlanes, ssbcFlatRowStates;
  GlFramebuffer ssbcFlatRows;
  // Interleaved direct light and gather in the deinterleaved block layout (gather.frag.glsl): k x k blocks of
  // blockWidth x blockHeight texels, reallocated when k changes.
  std::unique_ptr<Target> directRaw, indirectRaw;
  int rawInterleave = 0, blockWidth = 0, blockHeight = 0;

  void ensureRaw(int k) {
    if (rawInterleave == k) return;
    rawInterleave = k;
    blockWidth = (width + k - 1) / k;
    blockHeight = (height + k - 1) / k;
    directRaw = std::make_unique<Target>(blockWidth * k, blockHeight * k);
    indirectRaw = std::make_unique<Target>(blockWidth * k, blockHeight * k);
  }

  Targets(int w, int h)
      : width(w),
        height(h),
        gPosition(w, h, TextureFormat::Rgba32F, 0),
        gNormal(w, h, TextureFormat::Rgba32F, 0),
        gBaseColor(w, h, TextureFormat::Rgba32F),
        gEmission(w, h, TextureFormat::Rgba32F),
        gGeoNormal(w, h, TextureFormat::Rgba32F),
        gMergeKey(w, h, TextureFormat::Rgba32F),
        gDepth(w, h, TextureFormat::Depth32F),
        direct(w, h),
        indirect(w, h),
        i0(w, h, 0),
        r1(w, h, 0),
        r2(w, h),
        linear(w, h),
        display(w, h),
        rows(w, h),
        ssbcTaps(w, h, TextureFormat::Rgba32F, 0),
        ssbcArea(w, h, TextureFormat::R32F, 0),
        ssbcRadiance(w, h, TextureFormat::Rgba32F, 0),
        ssbcCoarse((w + 3) / 4, (h + 3) / 4),
        ssbcCoarseFar((w + 3) / 4, (h + 3) / 4, TextureFormat::Rgba32F),
        ssbcFlat((w + 3) / 4, (h + 3) / 4),
        ssbcFlatRowPlanes((w + 3) / 4, h, TextureFormat::Rgba32F),
        ssbcFlatRowStates((w + 3) / 4, h, TextureFormat::Rgba32F) {
    ssbcFlatRows.attachColor(0, ssbcFlatRowPlanes);
    ssbcFlatRows.attachColor(1, ssbcFlatRowStates);
    ssbcFlatRows.finalize(2);
    ssbcCoarse.framebuffer.attachColor(1, ssbcCoarseFar);
    ssbcCoarse.framebuffer.finalize(2);
    ssbcTapLevels.resize(static_cast<std::size_t>(ssbcTaps.levels()));
    ssbcRadianceLevels.resize(static_cast<std::size_t>(ssbcTaps.levels()));
    for (int level = 0; level < ssbcTaps.levels(); ++level) {
      ssbcTapLevels[static_cast<std::size_t>(level)].attachColor(0, ssbcTaps, level);
      ssbcTapLevels[static_cast<std::size_t>(level)].attachColor(1, ssbcArea, level);
      ssbcTapLevels[static_cast<std::size_t>(level)].finalize(2);
      ssbcRadianceLevels[static_cast<std::size_t>(level)].attachColor(0, ssbcRadiance, level);
      ssbcRadianceLevels[static_cast<std::size_t>(level)].finalize(1);
    }
    gbuffer.attachColor(0, gPosition);
    gbuffer.attachColor(1, gNormal);
    gbuffer.attachColor(2, gBaseColor);
    gbuffer.attachColor(3, gEmission);
    gbuffer.attachColor(4, gGeoNormal);
    gbuffer.attachColor(5, gMergeKey);
    gbuffer.attachDepth(gDepth);
    gbuffer.finalize(6);
  }

  void bindGbuffer() const {
    gPosition.bind(0);
    gNormal.bind(1);
    gBaseColor.bind(2);
    gEmission.bind(3);
    gGeoNormal.bind(4);
    gMergeKey.bind(10);
  }
};

namespace {
std::vector<std::string> withDefine(std::vector<std::string> defines, std::string define) {
  defines.push_back(std::move(define));
  return defines;
}
}  // namespace

BrdfVariants::BrdfVariants(const std::string& fragmentShader, const std::vector<std::string>& defines)
    : general({"preview/fullscreen.vert.glsl", fragmentShader}, defines),
      lambertOnly({"preview/fullscreen.vert.glsl", fragmentShader}, withDefine(defines, "BRDF_LAMBERT_ONLY 1")) {}

PreviewRenderer::PreviewRenderer()
    : gbuffer_({"preview/gbuffer.vert.glsl", "preview/gbuffer.frag.glsl"}),
      deinterleaveRows_({"preview/fullscreen.vert.glsl", "preview/deinterleave.frag.glsl"}, {"DEINTERLEAVE_COLUMNS 0"}),
      deinterleaveColumns_({"preview/fullscreen.vert.glsl", "preview/deinterleave.frag.glsl"},
                           {"DEINTERLEAVE_COLUMNS 1"}),
      compose_({"preview/fullscreen.vert.glsl", "preview/compose.frag.glsl"}),
      tonemap_({"preview/fullscreen.vert.glsl", "preview/tonemap.frag.glsl"}),
      direct_("preview/direct.frag.glsl", {uniformTableDefine("DIRECT_UBO_LIGHTS", sizeof(DirectLightGpu))}),
      ssbc_("preview/ssbc.frag.glsl"),
      ssbcTaps_({"preview/fullscreen.vert.glsl", "preview/ssbc_taps.frag.glsl"}),
      ssbcRadiance_({"preview/fullscreen.vert.glsl", "preview/ssbc_radiance.frag.glsl"}),
      ssbcSplit_("preview/ssbc.frag.glsl", {"SSBC_SPLIT 1"}),
      ssbcCoarse_("preview/ssbc.frag.glsl", {"SSBC_COARSE_PASS 1"}),
      ssbcFine_("preview/ssbc.frag.glsl", {"SSBC_SPLIT 1", "SSBC_FINE_PASS 1"}),
      ssbcFlatRows_({"preview/fullscreen.vert.glsl", "preview/ssbc_flat.frag.glsl"}, {"SSBC_FLAT_ROWS 1"}),
      ssbcFlatColumns_({"preview/fullscreen.vert.glsl", "preview/ssbc_flat.frag.glsl"}, {"SSBC_FLAT_ROWS 0"}),
      ssbcFallback_("preview/ssbc.frag.glsl", {"SSBC_SPLIT 1", "SSBC_FALLBACK_PASS 1"}),
      ssbcUpsample_("preview/ssbc.frag.glsl", {"SSBC_SPLIT 1", "SSBC_UPSAMPLE_PASS 1"}) {
  vplTable_ = uniformTableLayout(sizeof(VplGpu));
  directTable_ = uniformTableLayout(sizeof(DirectLightGpu));
  useVisibility(VisibilityMethod::Cube);
}

void PreviewRenderer::useVisibility(VisibilityMethod method) {
  if (vplVisibility_ && method == visibilityMethod_) return;
  vplVisibility_ = makeVplVisibility(method);
  visibilityMethod_ = method;
  const std::vector<std::string> defines = {uniformTableDefine("GATHER_UBO_VPLS", sizeof(VplGpu)),
                                            vplVisibility_->shaderDefine()};
  gather_ = std::make_unique<BrdfVariants>("preview/gather.frag.glsl", defines);
  gatherVsl_ = std::make_unique<BrdfVariants>("preview/gather_vsl.frag.glsl", defines);
}

PreviewRenderer::~PreviewRenderer() = default;

void PreviewRenderer::invalidateScene() {
  sceneDirty_ = true;
}
void PreviewRenderer::invalidateLights() {
  lightsDirty_ = true;
}
void PreviewRenderer::invalidateVpls() {
  vplsDirty_ = true;
}
void PreviewRenderer::invalidateFrame() {
  haveFrame_ = false;
}

void PreviewRenderer::ensureTargets(int width, int height) {
  if (targets_ && targets_->width == width && targets_->height == height) return;
  targets_ = std::make_unique<Targets>(width, height);
  haveFrame_ = false;
}

void PreviewRenderer::drawFullscreen(ShaderProgram& program) {
  program.use();
  vao_.bind();
  drawProceduralTriangles(3);
}

void PreviewRenderer::uploadDirectLights(const Scene& scene, const Settings& settings) {
  std::vector<DirectLightGpu> lights;
  lightCasters_.clear();
  // One shadow map per area emitter (light_shadows.h) and per punctual light.
  std::vector<AreaLightGroup> groups = groupAreaLights(scene);
  std::unordered_map<uint32_t, int> groupOf;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    for (uint32_t t : groups[g].triangles) groupOf[t] = static_cast<int>(g);
    lightCasters_.push_back({groups[g].centre, groups[g].radius});
  }
  // Area lights: K points y_k chosen with p(triangle) proportional to its power (luminance of its mean textured Le
  // x area, as the offline light sampler chooses) and uniform on the triangle, so p_A(y) = p_t / A_t; each carries
  // Le(y) / (K p_A), Le looked up at y, making the sum an unbiased estimate of the unshadowed T Le; the visibility
  // comes from the sample's emitter map.
  std::vector<float> cdf;
  std::vector<uint32_t> emitters;  // triangles with power > 0 (a black part of a textured emitter is never chosen)
  float total = 0.0f;
  for (uint32_t t : scene.emissiveTriangles) {
    float power = luminance(scene.meanEmission(t)) * scene.triangleArea(t);
    if (!(power > 0.0f)) continue;
    total += power;
    cdf.push_back(total);
    emitters.push_back(t);
  }
  if (total > 0.0f) {
    int k = settings.directLightSamples;
    // Sample s is Halton point s in bases 2 (the light choice) and 3, 5 (the point on the triangle), rotated by the
    // seed: deterministic (the same settings give the same samples, hence a stable preview) and stratified, so the
    // K samples cover the emitters evenly (independent random samples left errors of +-20 % at K = 64 where an
    // emitter is seen at grazing angles; these give +-3 %).
    Rng rotation(hashKey(settings.seed, 0x646972656374ull));
    const float offsetLight = rotation.next1D();
    const glm::vec2 offsetPoint = rotation.next2D();
    for (int s = 0; s < k; ++s) {
      const auto index = static_cast<uint64_t>(s);
      float u = rotateUnit(radicalInverse(2, index), offsetLight) * total;
      std::size_t i = static_cast<std::size_t>(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin());
      i = std::min(i, cdf.size() - 1);
      uint32_t tri = emitters[i];
      float pTri = (cdf[i] - (i ? cdf[i - 1] : 0.0f)) / total;
      glm::vec2 b = sampleUniformTriangle(
          {rotateUnit(radicalInverse(3, index), offsetPoint.x), rotateUnit(radicalInverse(5, index), offsetPoint.y)});
      const glm::uvec3& v = scene.triangles[tri];
      glm::vec3 y = b.x * scene.positions[v.x] + b.y * scene.positions[v.y] + (1.0f - b.x - b.y) * scene.positions[v.z];
      float pdfA = pTri / scene.triangleArea(tri);
      glm::vec3 weight =
          scene.emissionAt(scene.triangleMaterials[tri], scene.uvAt(tri, b)) / (static_cast<float>(k) * pdfA);
      const int g = groupOf.at(tri);
      const LightShadowCaster& caster = lightCasters_[static_cast<std::size_t>(g)];
      lights.push_back({glm::vec4(y, 0.0f), glm::vec4(scene.geometricNormal(tri), 0.0f), glm::vec4(weight, 0.0f),
                        glm::vec4(static_cast<float>(g), caster.radius, 0.0f, 0.0f), glm::vec4(caster.position, 0.0f)});
    }
    // Samples of one emitter next to each other: the shader filters its map once per run of them.
    std::stable_sort(lights.begin(), lights.end(),
                     [](const DirectLightGpu& a, const DirectLightGpu& b) { return a.shadow.x < b.shadow.x; });
  }
  directionalDirections_.clear();
  for (const PunctualLight& l : scene.punctualLights) {
    if (l.isDirectional()) {
      const float map = static_cast<float>(directionalDirections_.size());
      directionalDirections_.push_back(l.direction);
      lights.push_back({glm::vec4(0.0f, 0.0f, 0.0f, 3.0f), glm::vec4(l.direction, 0.0f), glm::vec4(l.intensity, 0.0f),
                        glm::vec4(map, 0.0f, 0.0f, 0.0f), glm::vec4(0.0f)});
      continue;
    }
    bool spot = l.type == PunctualLight::Type::Spot;
    const float cube = static_cast<float>(lightCasters_.size());
    lightCasters_.push_back({l.position, 0.0f});
    lights.push_back({glm::vec4(l.position, spot ? 2.0f : 1.0f), glm::vec4(l.direction, std::cos(l.outerConeAngle)),
                      glm::vec4(l.intensity, std::cos(l.innerConeAngle)), glm::vec4(cube, 0.0f, 0.0f, 0.0f),
                      glm::vec4(l.position, 0.0f)});
  }
  directLightCount_ = static_cast<int>(lights.size());
  directLights_.assign(lights.data(), lights.size() * sizeof(DirectLightGpu));
}

void PreviewRenderer::uploadVpls(const Scene& scene, const VplSet& set) {
  std::vector<VplGpu> gpu(set.vpls.size());
  vplsHaveRadius_ = false;
  for (std::size_t i = 0; i < gpu.size(); ++i) {
    const Vpl& v = set.vpls[i];
    vplsHaveRadius_ = vplsHaveRadius_ || v.radius > 0.0f;
    const Material& m = scene.materials[v.material];
    gpu[i] = {glm::vec4(v.position, v.radius),
              glm::vec4(v.normal, m.metallic),
              glm::vec4(v.incoming, m.roughness),
              glm::vec4(v.flux, m.specular),
              glm::vec4(scene.baseColorAt(v.material, v.uv), 0.0f),
              glm::vec4(v.geometricNormal, 0.0f),
              glm::vec4(0.0f)};
    // The pure-Lambert gather's whole VPL factor f(x2) Phi = albedo / pi Phi, 0 where the light arrived from behind
    // the shading normal (common/gather.glsl).
    if (glm::dot(v.normal, v.incoming) > 0.0f)
      gpu[i].lambertPower = glm::vec4(glm::vec3(gpu[i].baseColor) * v.flux * kInvPi, 0.0f);
  }
  vplBuffer_.assign(gpu.data(), gpu.size() * sizeof(VplGpu));
}

std::string previewFitProblem(const Scene& scene, std::size_t vplCount, const Settings& settings,
                              const GlLimits& limits) {
  std::ostringstream why;
  const int largest = std::min(limits.maxTextureSize, limits.maxFramebufferSize);
  if (settings.width > largest || settings.height > largest) {
    why << "image size " << settings.width << "x" << settings.height << " exceeds this GL context's largest render target "
        << largest << ": lower --size";
    return why.str();
  }
  VisibilityFootprint vplMaps =
      visibilityFootprint(settings.visibility, static_cast<int>(vplCount), settings, limits);
  if (!vplMaps.problem.empty()) return vplMaps.problem;
  // The screen targets (Targets: G-buffer, interleaved and merged results, compensation mips and rings), counted as 40
  // RGBA32F-sized texels per pixel, an upper bound.
  const double targetBytes = 40.0 * 16.0 * settings.width * settings.height;
  // The lights' maps: an R32F cube per area-light group and per point or spot light, an R32F square per directional.
  int cubes = scene.emissiveTriangles.empty() ? 0 : kMaxAreaGroups, squares = 0;
  for (const PunctualLight& l : scene.punctualLights) (l.isDirectional() ? squares : cubes) += 1;
  const double lightBytes = 4.0 * (6.0 * cubes * kLightShadowFaceSize * kLightShadowFaceSize +
                                   static_cast<double>(squares) * kDirectionalShadowSize * kDirectionalShadowSize);
  const double total = vplMaps.bytes + targetBytes + lightBytes;
  if (total > limits.memoryBytes)
    why << vplMaps.what << " need " << formatBytes(vplMaps.bytes) << "; with the " << settings.width << "x"
        << settings.height << " targets and up to " << cubes + squares << " light shadow map(s) the preview needs "
        << formatBytes(total) << ", over the " << formatBytes(limits.memoryBytes) << " it allows itself here (half the "
        << limits.memorySource << "): lower --vpls, --size or "
        << (settings.visibility == VisibilityMethod::Ism ? "--ism-tile-size" : "--shadow-map-size, or use --visibility ism");
  return why.str();
}

PreviewTimings PreviewRenderer::render(const Scene& scene, const VplSet& vpls, const Settings& settings,
                                       const Camera& camera, double budgetMs) {
  auto frameStart = std::chrono::steady_clock::now();
  requireValidSettings(settings);
  if (limits_.maxTextureSize == 0) limits_ = queryGlLimits();
  if (std::string problem = previewFitProblem(scene, vpls.vpls.size(), settings, limits_); !problem.empty())
    throw std::runtime_error(problem);
  PreviewTimings t;
  if (&scene != scene_ || sceneDirty_ || !glScene_) {
    glScene_ = std::make_unique<GlScene>(scene);
    scene_ = &scene;
    // The same test as evaluateBrdf's Lambert fast path (metallic and specular are per material, never textured).
    lambertOnly_ = std::all_of(scene.materials.begin(), scene.materials.end(),
                               [](const Material& m) { return m.metallic <= 0.0f && m.specular <= 0.0f; });
    sceneDirty_ = false;
    haveFrame_ = false;
    shadowsValid_ = false;
    vplsDirty_ = true;
  }
  if (&vpls != vplSet_) vplsDirty_ = true;
  vplSet_ = &vpls;
  ensureTargets(settings.width, settings.height);
  Targets& tg = *targets_;
  const Settings& last = lastSettings_;

  // Invalidation (header comment): decide which passes the changes since the last frame affect.
  bool cameraChanged = !haveFrame_ || !sameCamera(camera, lastCamera_);
  // The lights' maps depend on the scene and the light samples (K, seed) only.
  bool directMapsChanged = !shadowsValid_ || lightsDirty_ || settings.directLightSamples != last.directLightSamples ||
                           settings.seed != last.seed;
  lightsDirty_ = false;
  if (settings.visibility != visibilityMethod_) {
    useVisibility(settings.visibility);
    vplsDirty_ = true;
  }
  if (!shadowsValid_) vplVisibility_->resetScene();
  // The VPL maps depend on the casters (position, and orientation for paraboloid tiles) only: flux, radius or material
  // edits just re-upload the VPLs.
  bool vplDataChanged = vplsDirty_;
  std::vector<IsmCaster> casters(vpls.vpls.size());
  for (std::size_t i = 0; i < casters.size(); ++i) casters[i] = {vpls.vpls[i].position, vpls.vpls[i].geometricNormal};
  bool vplMapsChanged = vplVisibility_->stale(casters, settings);
  bool directChanged = cameraChanged || directMapsChanged || settings.shadowBias != last.shadowBias ||
                       settings.interleave != last.interleave;
  bool gatherChanged = cameraChanged || vplDataChanged || vplMapsChanged || settings.clampBound != last.clampBound ||
                       settings.interleave != last.interleave ||
                       settings.shadowBias != last.shadowBias;
  bool ssbcChanged = directChanged || gatherChanged || settings.ssbcSteps != last.ssbcSteps ||
                     settings.ssbcCoarseRings != last.ssbcCoarseRings;
  bool tonemapChanged = ssbcChanged || settings.exposure != last.exposure;

  // What this call found stale joins what earlier calls left undone (a budget cut them short); the passes then run in
  // order from the first pending one until the budget is spent.
  const bool jobRunning = pending_.any();
  pending_.gbuffer |= cameraChanged;
  pending_.directMaps |= directMapsChanged;
  pending_.vplMaps |= vplMapsChanged;
  pending_.direct |= directChanged;
  // A gather sliced over earlier calls starts over when what it depends on changed again.
  if (gatherChanged) gatherNextDraw_ = 0;
  pending_.gather |= gatherChanged;
  pending_.merge |= directChanged || gatherChanged;
  pending_.ssbc |= ssbcChanged;
  pending_.tonemap |= tonemapChanged;
  if (!jobRunning) jobDone_ = 0;
  jobTotal_ = jobDone_ + pending_.count();
  haveFrame_ = true;
  lastCamera_ = camera;
  lastSettings_ = settings;
  cameraChanged = pending_.gbuffer;
  directMapsChanged = pending_.directMaps;
  vplMapsChanged = pending_.vplMaps;
  directChanged = pending_.direct;
  gatherChanged = pending_.gather;
  ssbcChanged = pending_.ssbc;
  tonemapChanged = pending_.tonemap;
  // A pass runs only while no earlier pass of this call has spent the budget; each clears its pending flag.
  bool outOfBudget = false;
  auto finished = [&](bool& flag) {
    flag = false;
    ++jobDone_;
    outOfBudget = msSince(frameStart) > budgetMs;
  };

  float diagonal = std::max(scene.bounds.diagonal(), 1e-6f);
  float far = 2.0f * diagonal;
  float bias = settings.shadowBias * diagonal;
  // The bounding sphere a directional light's map covers, a little larger so that no surface lies on its rim.
  const float sceneRadius = 0.51f * diagonal;
  glm::mat4 view = glm::lookAt(camera.position, camera.position + camera.forward, camera.up);
  float aspect = static_cast<float>(settings.width) / static_cast<float>(settings.height);
  glm::mat4 proj = glm::perspective(camera.yfov, aspect, camera.znear, camera.zfar);
  glDisable(GL_BLEND);
  glDisable(GL_DEPTH_TEST);

  // Pass 1: G-buffer.
  if (cameraChanged) {
    t.gbufferMs = timed(timer_, t.gbufferWallMs, [&] {
      tg.gbuffer.bind(tg.width, tg.height);
      // Background texels are marked by w = 0 in position and merge key; the normal's mips must average zeros there
      // (a short averaged normal flags an edge). The other targets are only read where position.w > 0.
      for (int i : {0, 1, 5}) tg.gbuffer.clearColor(i, glm::vec4(0.0f));
      tg.gbuffer.clearDepth(1.0f);
      glEnable(GL_DEPTH_TEST);
      glDepthFunc(GL_LESS);
      glDisable(GL_CULL_FACE);
      glScene_->bind(5);
      gbuffer_.set("uViewProj", proj * view);
      gbuffer_.set("uCameraPosition", camera.position);
      gbuffer_.use();
      vao_.bind();
      drawProceduralTriangles(3 * glScene_->triangleCount());
      glDisable(GL_DEPTH_TEST);
      tg.gbufferMipsCurrent = false;
    });
    ++counters_.gbuffer;
    finished(pending_.gbuffer);
  }

  // Shadow maps of the direct-light samples: depend on the scene, K, the seed and the map size only.
  if (directMapsChanged && !outOfBudget) {
    t.directShadowMs = timed(timer_, t.directShadowWallMs, [&] {
      uploadDirectLights(scene, settings);
      lightShadows_.render(*glScene_, lightCasters_, kLightShadowFaceSize, far);
      lightShadows_.renderDirectional(*glScene_, directionalDirections_, scene.bounds.center(), sceneRadius,
                                      kDirectionalShadowSize);
    });
    ++counters_.directShadowMaps;
    finished(pending_.directMaps);
  }

  if (vplDataChanged) uploadVpls(scene, vpls);
  vplsDirty_ = false;
  // Pass 3: the VPLs' visibility maps, only when a VPL position (or the map size, or the scene) changes. A technique
  // that builds them in slices stops when the budget is spent and goes on in the next call.
  if (vplMapsChanged && !outOfBudget) {
    bool built = false;
    t.vplShadowMs = timed(timer_, t.vplShadowWallMs, [&] {
      built = vplVisibility_->update(*glScene_, scene, casters, settings, far,
                                     [&] { return msSince(frameStart) > budgetMs; });
    });
    if (built) {
      ++counters_.vplShadowMaps;
      finished(pending_.vplMaps);
    } else {
      outOfBudget = true;
    }
  }
  shadowsValid_ = true;

  tg.bindGbuffer();
  tg.ensureRaw(settings.interleave);
  const int k = settings.interleave;
  // Draws a light table (direct-light samples or VPLs, common/interleaved.glsl) with `program` into the deinterleaved
  // layout of `raw` (gather.frag.glsl): for each interleaving subset, one draw per range of a shadow-map chunk that
  // fits `layout`'s uniform block. A single draw per subset replaces its block's texels (every fragment writes), so it
  // needs neither a clear nor blending; several draws add up. The merge of the subsets follows both passes.
  // With a cursor, the draws from *cursor on run until the budget is spent (a draw's sum is complete on its own, so
  // the rest can follow in the next call): returns false and leaves *cursor at the first draw not made, or true after
  // the last one.
  auto drawLightTable = [&](ShaderProgram& program, Target& raw, const auto& shadows, auto&& bindChunk,
                            const UniformTableLayout& layout, const GlBuffer& table, int binding,
                            int* cursor = nullptr) {
    struct Range {
      int chunk, base, begin, end;
    };
    std::vector<Range> ranges;
    for (int c = 0; c < shadows.chunkCount(); ++c)
      forEachUniformRange(layout, shadows.chunkBegin(c), shadows.chunkEnd(c),
                          [&](int base, int begin, int end) { ranges.push_back({c, base, begin, end}); });
    const int perSubset = static_cast<int>(ranges.size()), total = k * k * perSubset;
    const int first = cursor ? *cursor : 0;
    raw.framebuffer.bind(tg.blockWidth * k, tg.blockHeight * k);
    if (perSubset != 1 && first == 0) raw.framebuffer.clearColor(0, glm::vec4(0.0f));
    program.set("uInterleave", k);
    program.set("uImageSize", glm::ivec2(tg.width, tg.height));
    if (perSubset > 1) {
      glEnable(GL_BLEND);
      glBlendFunc(GL_ONE, GL_ONE);
    }
    bool done = true;
    int boundChunk = -1;
    for (int draw = first; draw < total; ++draw) {
      const int subset = draw / perSubset;
      const Range& r = ranges[static_cast<std::size_t>(draw % perSubset)];
      const int sx = subset % k, sy = subset / k;
      glm::ivec2 origin(sx * tg.blockWidth, sy * tg.blockHeight);
      glViewport(origin.x, origin.y, tg.blockWidth, tg.blockHeight);
      program.set("uSubsetXY", glm::ivec2(sx, sy));
      program.set("uBlockOrigin", origin);
      if (r.chunk != boundChunk) {
        bindChunk(r.chunk);
        program.set("uFirstLight", shadows.chunkBegin(r.chunk));
        boundChunk = r.chunk;
      }
      table.bindUniformRange(binding, static_cast<std::size_t>(r.base) * layout.elementBytes,
                             static_cast<std::size_t>(r.end - r.base) * layout.elementBytes);
      program.set("uUboBase", r.base);
      program.set("uLightBegin", r.begin);
      program.set("uSubsetOffset", subsetOffset(r.begin, subset, k));
      program.set("uLightEnd", r.end);
      drawFullscreen(program);
      if (cursor && std::isfinite(budgetMs) && draw + 1 < total) {
        glFinish();  // the time spent is known only once the GPU has made the draw
        if (msSince(frameStart) > budgetMs) {
          *cursor = draw + 1;
          done = false;
          break;
        }
      }
    }
    if (done && cursor) *cursor = 0;
    glDisable(GL_BLEND);
    return done;
  };

  tg.bindGbuffer();
  // Pass 2: direct light, additive over shadow-map chunks, interleaved over the light samples.
  if (directChanged && !outOfBudget) {
    t.directMs = timed(timer_, t.directWallMs, [&] {
      ShaderProgram& direct = direct_[lambertOnly_];
      direct.set("uCameraPosition", camera.position);
      direct.set("uLightShadowTexel", 2.0f / static_cast<float>(kLightShadowFaceSize));
      direct.set("uSceneCentre", scene.bounds.center());
      direct.set("uSceneRadius", sceneRadius);
      direct.set("uDirectionalShadowTexel", 2.0f * sceneRadius / static_cast<float>(kDirectionalShadowSize));
      lightShadows_.bind();
      // The whole light table is one chunk: every light's map is a layer of one cube-map array.
      drawLightTable(direct, *tg.directRaw, SingleChunk{directLightCount_}, [](int) {}, directTable_, directLights_, 7);
    });
    ++counters_.direct;
    finished(pending_.direct);
  }

  // Pass 4: VPL gather with G_b / VSL and interleaving (the de-interleave follows), draw by draw when a budget is
  // given.
  if (gatherChanged && !outOfBudget) {
    bool gathered = false;
    t.gatherMs = timed(timer_, t.gatherWallMs, [&] {
      // A set without VSLs uses the variant without the cone integral (common/gather.glsl).
      ShaderProgram& gather = (vplsHaveRadius_ ? *gatherVsl_ : *gather_)[lambertOnly_];
      gather.set("uCameraPosition", camera.position);
      gather.set("uClampBound", settings.clampBound);
      gather.set("uShadowFar", far);
      gather.set("uShadowBias", bias);
      const VplVisibility& visibility = *vplVisibility_;
      // At most kGatherVplsPerDraw VPLs per pixel and draw, so that a budget can stop between draws; the same split
      // with or without a budget, so that both sum in the same order and give the same image.
      UniformTableLayout sliced = vplTable_;
      sliced.capacity = std::max(sliced.alignment, std::min(sliced.capacity, kGatherVplsPerDraw * k * k));
      gathered = drawLightTable(
          gather, *tg.indirectRaw, visibility, [&](int c) { visibility.bindChunk(c, gather); }, sliced, vplBuffer_, 8,
          &gatherNextDraw_);
    });
    if (gathered) {
      ++counters_.gather;
      finished(pending_.gather);
    } else {
      outOfBudget = true;
    }
  }

  // Geometry-aware de-interleave of the direct light and the gather together into I0 (deinterleave.frag.glsl): the
  // merge is linear and its weights depend on the G-buffer only, so one merge serves both. Its time is counted in the
  // gather pass (in the direct pass when only that one ran).
  if (pending_.merge && !pending_.direct && !pending_.gather && !outOfBudget) {
    double wallMs = 0.0;
    double gpuMs = timed(timer_, wallMs, [&] { mergeInterleaved(glm::vec2(1.0f), tg.i0.framebuffer); });
    t.deinterleaveMs = gpuMs;
    (gatherChanged ? t.gatherMs : t.directMs) += gpuMs;
    (gatherChanged ? t.gatherWallMs : t.directWallMs) += wallMs;
    finished(pending_.merge);
  }

  // Pass 5: R1 = T_r(I0) (I0 = direct + indirect, merged by the de-interleave), R2 = T_r(R1), final = Le + I0 + R1
  // + R2 (the final composition reads R1 and R2 itself; readLinear(PreviewOutput::Residual) sums them on demand).
  if (ssbcChanged && !pending_.merge && !outOfBudget) {
    t.ssbcMs = timed(timer_, t.ssbcWallMs, [&] {
      bool compensate = settings.ssbcSteps > 0 && std::isfinite(settings.clampBound) && settings.clampBound > 0.0f;
      residualSteps_ = compensate ? std::min(settings.ssbcSteps, 2) : 0;
      if (compensate) {
        float focal = 0.5f * static_cast<float>(tg.height) / std::tan(0.5f * camera.yfov);
        const bool split = settings.ssbcCoarseRings;
        ShaderProgram& ssbc = split ? ssbcSplit_[lambertOnly_] : ssbc_[lambertOnly_];
        ShaderProgram& coarse = ssbcCoarse_[lambertOnly_];
        ShaderProgram& fallback = ssbcFallback_[lambertOnly_];
        ShaderProgram& fine = ssbcFine_[lambertOnly_];
        ShaderProgram& upsample = ssbcUpsample_[lambertOnly_];
        for (ShaderProgram* program : {&ssbc, &coarse, &fallback, &fine, &upsample}) {
          program->set("uCameraPosition", camera.position);
          program->set("uCameraForward", camera.forward);
          program->set("uClampBound", settings.clampBound);
          program->set("uFocalPixels", focal);
          program->set("uMaxLevel", tg.gPosition.levels() - 1);
        }
        ssbc.set("uScale", 1);
        coarse.set("uScale", 4);
        fallback.set("uScale", 1);
        fine.set("uScale", 1);
        upsample.set("uScale", 1);
        // Draws `program` into every mip level of a full-resolution texture (one framebuffer per level), uLevel set.
        auto drawEveryLevel = [&](std::vector<GlFramebuffer>& levels, ShaderProgram& program) {
          for (std::size_t level = 0; level < levels.size(); ++level) {
            const int l = static_cast<int>(level);
            levels[level].bind(std::max(1, tg.width >> l), std::max(1, tg.height >> l));
            program.set("uLevel", l);
            drawFullscreen(program);
          }
        };
        // Multi-resolution rings: adds (blending) the fine rings where they are not zero, and (withFallback) the
        // coarse rings where the pass before could not interpolate them from the coarse grid.
        auto addSplitPasses = [&](bool withFallback) {
          if (!split) return;
          glEnable(GL_BLEND);
          glBlendFunc(GL_ONE, GL_ONE);
          drawFullscreen(fine);
          if (withFallback) drawFullscreen(fallback);
          glDisable(GL_BLEND);
        };
        if (split) {
          // Which coarse blocks lie on one plane: depends on the camera and the G-buffer only, once for both steps.
          tg.ssbcFlatRows.bind(tg.ssbcFlat.texture.width(), tg.height);
          drawFullscreen(ssbcFlatRows_);
          tg.ssbcFlatRowPlanes.bind(11);
          tg.ssbcFlatRowStates.bind(13);
          tg.ssbcFlat.framebuffer.bind(tg.ssbcFlat.texture.width(), tg.ssbcFlat.texture.height());
          drawFullscreen(ssbcFlatColumns_);
          tg.ssbcFlat.texture.bind(14);
        }
        // Mips of position and normal feed the hierarchical compensation (coverage and normal length flag edges):
        // made here, so that a frame without compensation does not pay for them.
        if (!tg.gbufferMipsCurrent) {
          tg.gPosition.generateMipmaps();
          tg.gNormal.generateMipmaps();
          tg.gbufferMipsCurrent = true;
        }
        // The tap factors depend on the camera and the G-buffer only: once per frame, for both steps.
        ssbcTaps_.set("uCameraPosition", camera.position);
        ssbcTaps_.set("uFocalPixels", focal);
        drawEveryLevel(tg.ssbcTapLevels, ssbcTaps_);
        tg.ssbcTaps.bind(9);
        tg.ssbcArea.bind(12);
        Target* input = &tg.i0;
        Target* outputs[2] = {&tg.r1, &tg.r2};
        for (int step = 0; step < settings.ssbcSteps; ++step) {
          // The radiance factor of the taps, I dA, at every mip level of this step's input.
          input->texture.generateMipmaps();
          input->texture.bind(6);
          drawEveryLevel(tg.ssbcRadianceLevels, ssbcRadiance_);
          tg.ssbcRadiance.bind(6);
          if (split) {
            tg.ssbcCoarse.framebuffer.bind(tg.ssbcCoarse.texture.width(), tg.ssbcCoarse.texture.height());
            drawFullscreen(coarse);
            tg.ssbcCoarse.texture.bind(11);
            tg.ssbcCoarseFar.bind(13);
          }
          outputs[step]->framebuffer.bind(tg.width, tg.height);
          // R2 = T_r(R1) carries about a tenth of the compensation: there the coarse rings are extrapolated along
          // p's surface where they cannot be interpolated, instead of being evaluated at those pixels.
          const bool extrapolate = split && step == 1;
          drawFullscreen(extrapolate ? upsample : ssbc);
          addSplitPasses(!extrapolate);
          input = outputs[step];
        }
      }
      tg.bindGbuffer();
      tg.i0.texture.bind(6);
      tg.r1.texture.bind(8);
      tg.r2.texture.bind(9);
      tg.linear.framebuffer.bind(tg.width, tg.height);
      compose_.set("uResidualSteps", residualSteps_);
      compose_.set("uCameraPosition", camera.position);
      drawFullscreen(compose_);
    });
    ++counters_.ssbc;
    finished(pending_.ssbc);
  }

  // Pass 6: tonemap.
  if (tonemapChanged && !pending_.ssbc && !outOfBudget) {
    t.tonemapMs = timed(timer_, t.tonemapWallMs, [&] {
      tg.display.framebuffer.bind(tg.width, tg.height);
      tg.linear.texture.bind(6);
      tonemap_.set("uExposureScale", std::exp2(settings.exposure));
      drawFullscreen(tonemap_);
    });
    ++counters_.tonemap;
    finished(pending_.tonemap);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  checkGlError("PreviewRenderer::render");

  if (gatherChanged && !pending_.gather)
    t.gatherEvaluations = static_cast<double>(settings.width) * settings.height *
                          static_cast<double>(vpls.vpls.size()) /
                          static_cast<double>(settings.interleave * settings.interleave);
  t.frameWallMs = msSince(frameStart);
  t.complete = !pending_.any();
  t.progress = jobTotal_ > 0 ? static_cast<float>(jobDone_) / static_cast<float>(jobTotal_) : 1.0f;
  return t;
}

void PreviewRenderer::mergeInterleaved(glm::vec2 weights, GlFramebuffer& out) {
  Targets& tg = *targets_;
  const int k = tg.rawInterleave;
  // Rows, then columns (separable: 2k neighbours per pixel instead of k^2).
  tg.rows.framebuffer.bind(tg.width, tg.height);
  tg.gMergeKey.bind(10);
  tg.directRaw->texture.bind(6);
  tg.indirectRaw->texture.bind(7);
  deinterleaveRows_.set("uInterleave", k);
  deinterleaveRows_.set("uBlockSize", glm::ivec2(tg.blockWidth, tg.blockHeight));
  deinterleaveRows_.set("uWeights", weights);
  drawFullscreen(deinterleaveRows_);
  out.bind(tg.width, tg.height);
  tg.rows.texture.bind(6);
  deinterleaveColumns_.set("uInterleave", k);
  drawFullscreen(deinterleaveColumns_);
}

Image PreviewRenderer::readLinear(PreviewOutput which) {
  if (!targets_) return {};
  Targets& tg = *targets_;
  if (which == PreviewOutput::Residual) {
    // R1 + R2: the final composition adds them itself, so the sum is formed only when asked for.
    Image residual(tg.width, tg.height);
    for (int step = 0; step < residualSteps_; ++step) {
      Image r = readFramebuffer((step == 0 ? tg.r1 : tg.r2).framebuffer, 0, tg.width, tg.height);
      for (std::size_t i = 0; i < residual.size(); ++i) residual.pixels[i] += r.pixels[i];
    }
    return residual;
  }
  if (which == PreviewOutput::Direct || which == PreviewOutput::Indirect) {
    // A frame merges only their sum I0; one component is merged from the interleaved passes' results on demand.
    if (!tg.directRaw) return {};
    const bool direct = which == PreviewOutput::Direct;
    Target& out = direct ? tg.direct : tg.indirect;
    mergeInterleaved(direct ? glm::vec2(1.0f, 0.0f) : glm::vec2(0.0f, 1.0f), out.framebuffer);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return readFramebuffer(out.framebuffer, 0, tg.width, tg.height);
  }
  return readFramebuffer(tg.linear.framebuffer, 0, tg.width, tg.height);
}

Image PreviewRenderer::readTonemapped() const {
  if (!targets_) return {};
  return readFramebuffer(targets_->display.framebuffer, 0, targets_->width, targets_->height);
}

}  // namespace vplab
