#include "renderer/gl/preview_renderer.h"

#include <glad/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <glm/gtc/matrix_transform.hpp>
#include <sstream>
#include <stdexcept>
#include <string>

#include "renderer/gl/texture_units.h"
#include "renderer/invalidation.h"
#include "renderer/scene/density_grid.h"

namespace vplab {

namespace {

// A perspective projection with depth = znear / z_view in [0, 1] (clip control GL_ZERO_TO_ONE): 1 at the near plane,
// 0 at infinity, no far plane (as the reference's camera rays have none).
glm::mat4 reversedDepthProjection(float yfov, float aspect, float znear) {
  const float f = 1.0f / std::tan(0.5f * yfov);
  glm::mat4 m(0.0f);
  m[0][0] = f / aspect;
  m[1][1] = f;
  m[3][2] = znear;
  m[2][3] = -1.0f;
  return m;
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

/// The G-buffer's colour textures (common/fullscreen.glsl, gbuffer.frag.glsl) at one resolution, attached to one
/// framebuffer.
struct GbufferTextures {
  GlTexture position, normal, baseColor, emission, shading, mergeKey, surface;
  GlFramebuffer framebuffer;

  GbufferTextures(int w, int h)
      : position(w, h, TextureFormat::Rgba32F),
        normal(w, h, TextureFormat::Rgba32F),
        baseColor(w, h, TextureFormat::Rgba32F),
        emission(w, h, TextureFormat::Rgba32F),
        shading(w, h, TextureFormat::Rgba32UI),
        mergeKey(w, h, TextureFormat::Rgba32F),
        surface(w, h, TextureFormat::Rgba32UI) {
    framebuffer.attachColor(0, position);
    framebuffer.attachColor(1, normal);
    framebuffer.attachColor(2, baseColor);
    framebuffer.attachColor(3, emission);
    framebuffer.attachColor(4, shading);
    framebuffer.attachColor(5, mergeKey);
    framebuffer.attachColor(6, surface);
  }

  void bind() const {
    position.bind(unit(TextureUnit::GPosition));
    normal.bind(unit(TextureUnit::GNormal));
    baseColor.bind(unit(TextureUnit::GBaseColor));
    emission.bind(unit(TextureUnit::GEmission));
    shading.bind(unit(TextureUnit::GShading));
    mergeKey.bind(unit(TextureUnit::GMergeKey));
    surface.bind(unit(TextureUnit::GSurface));
  }
};

/// The pixels the interleaved passes, their de-interleave and the compensation run on: the image's own, or the
/// indirect light's grid at 1/s of its width and height (Settings::indirectDownscale, common/downscale.glsl).
struct ScreenGrid {
  int width, height;
  GbufferTextures g;
  // Whether what the compensation derives from the G-buffer alone (tap factors, flat blocks) was made from the current
  // G-buffer: a VPL change does not redo it.
  bool gbufferDerivedCurrent = false;
  // The de-interleaved gather: every frame on the indirect light's own grid; on the image's grid only when a component
  // is read back (readLinear), so it is made when first asked for (llvmpipe zero-fills what it allocates).
  std::unique_ptr<Target> indirectMerged;
  Target& indirect() {
    if (!indirectMerged) indirectMerged = std::make_unique<Target>(width, height);
    return *indirectMerged;
  }
  // Row sums of the separable de-interleave (deinterleave.frag.glsl), accepted count in w.
  Target rows;
  // What only the grid the indirect light is gathered on needs (Targets::indirectGrid() makes it): I0 = direct +
  // indirect, the compensation's input, and its steps' results R1 and R2; the light arriving per unit of reflectance
  // that an upsample interpolates, and the planes of flat 2x2 blocks (upsample.frag.glsl; a grid of its own). Not
  // made at the image's size when the indirect light has a grid of its own: llvmpipe zero-fills every texture it
  // allocates, 28 MB of page faults at 640x480 in a cold start.
  struct IndirectResults {
    Target i0, r1, r2, light;
    GlTexture blockPlane;
    IndirectResults(int w, int h)
        : i0(w, h), r1(w, h), r2(w, h), light(w, h), blockPlane(w, h, TextureFormat::Rgba32F) {
      light.texture.setLinearFiltering(true);
      light.texture.setRepeat(false);
      light.framebuffer.attachColor(1, blockPlane);
      light.framebuffer.finalize(2);
    }
  };
  std::unique_ptr<IndirectResults> indirectResults;
  IndirectResults& results() { return *indirectResults; }
  // Interleaved direct light of the area-light samples (on the image's own grid only) and gather in the deinterleaved
  // block layout (gather.frag.glsl): k x k blocks of blockWidth x blockHeight texels, reallocated when k changes.
  std::unique_ptr<Target> directRaw, indirectRaw;
  // The punctual lights' direct light at every pixel, which the merge adds (the image's own grid, in a scene with such
  // lights).
  std::unique_ptr<Target> punctualDirect;
  int rawInterleave = 0, blockWidth = 0, blockHeight = 0;

  ScreenGrid(int w, int h) : width(w), height(h), g(w, h), rows(w, h) {}

  void ensureRaw(int k, bool withDirect, bool withPunctual) {
    if (!withPunctual) punctualDirect.reset();
    else if (!punctualDirect) punctualDirect = std::make_unique<Target>(width, height);
    if (rawInterleave == k && static_cast<bool>(directRaw) == withDirect) return;
    rawInterleave = k;
    blockWidth = (width + k - 1) / k;
    blockHeight = (height + k - 1) / k;
    directRaw = withDirect ? std::make_unique<Target>(blockWidth * k, blockHeight * k) : nullptr;
    indirectRaw = std::make_unique<Target>(blockWidth * k, blockHeight * k);
  }
  InterleavedLayout interleaved() const { return {width, height, rawInterleave, blockWidth, blockHeight}; }
};

struct PreviewRenderer::Targets {
  int width, height;
  ScreenGrid full;
  GlTexture gDepth;
  // The de-interleaved direct light (a frame merges it into I0 with the gather when the grid is the image's own) and
  // the final linear image.
  Target direct, linear;
  // The indirect light's grid when Settings::indirectDownscale > 1, and its s.
  std::unique_ptr<ScreenGrid> downscaled;
  int downscale = 1;
  // Whether the direct light was drawn since `direct` was last merged from it (only then does a grid of its own need
  // the merge again).
  bool directMergeStale = true;

  Targets(int w, int h)
      : width(w),
        height(h),
        full(w, h),
        gDepth(w, h, TextureFormat::Depth32F),
        direct(w, h),
        linear(w, h) {
    full.g.framebuffer.attachDepth(gDepth);
    full.g.framebuffer.finalize(7);
  }

  void ensureDownscale(int s) {
    if (s == downscale) return;
    downscale = s;
    downscaled.reset();
    if (s > 1) {
      const glm::ivec2 size = indirectGridSize(width, height, s);
      downscaled = std::make_unique<ScreenGrid>(size.x, size.y);
      downscaled->g.framebuffer.finalize(7);
    }
  }
  /// Where the gather and the compensation run.
  ScreenGrid& indirectGrid() {
    ScreenGrid& grid = downscaled ? *downscaled : full;
    if (!grid.indirectResults)
      grid.indirectResults = std::make_unique<ScreenGrid::IndirectResults>(grid.width, grid.height);
    return grid;
  }
};

PreviewRenderer::PreviewRenderer()
    : gbufferTextured_({"preview/gbuffer.vert.glsl", "preview/gbuffer.frag.glsl"}, {"SCENE_TEXTURED 1"}),
      gbufferUntextured_({"preview/gbuffer.vert.glsl", "preview/gbuffer.frag.glsl"}, {"SCENE_TEXTURED 0"}),
      gbufferBackground_({"preview/fullscreen.vert.glsl", "preview/gbuffer_background.frag.glsl"}),
      deinterleaveRows_({"preview/fullscreen.vert.glsl", "preview/deinterleave.frag.glsl"}, {"DEINTERLEAVE_COLUMNS 0"}),
      deinterleaveRowsOneInput_({"preview/fullscreen.vert.glsl", "preview/deinterleave.frag.glsl"},
                                {"DEINTERLEAVE_COLUMNS 0", "DEINTERLEAVE_ONE_INPUT 1"}),
      deinterleaveColumns_({"preview/fullscreen.vert.glsl", "preview/deinterleave.frag.glsl"},
                           {"DEINTERLEAVE_COLUMNS 1"}),
      gridGbuffer_({"preview/fullscreen.vert.glsl", "preview/indirect_grid.frag.glsl"}, {"INDIRECT_GRID_GBUFFER 1"}),
      gridInput_({"preview/fullscreen.vert.glsl", "preview/indirect_grid.frag.glsl"}, {"INDIRECT_GRID_GBUFFER 0"}),
      compose_({"preview/fullscreen.vert.glsl", "preview/compose.frag.glsl"}),
      gridLight_({"preview/fullscreen.vert.glsl", "preview/upsample.frag.glsl"}, {"UPSAMPLE_GRID_LIGHT 1"}),
      upsample_({"preview/fullscreen.vert.glsl", "preview/upsample.frag.glsl"}, {"UPSAMPLE_GRID_LIGHT 0"}) {
  useVisibility(VisibilityMethod::Cube, {});
}

void PreviewRenderer::useVisibility(VisibilityMethod method, const MediaShaderLayout& media) {
  if (vplVisibility_ && method == visibilityMethod_ && media == gatherMedia_) return;
  if (!vplVisibility_ || method != visibilityMethod_) vplVisibility_ = makeVplVisibility(method);
  visibilityMethod_ = method;
  gatherMedia_ = media;
  gather_.useVisibility(*vplVisibility_, media);
  if (media.count > 0) media_.useGatherDefines(gather_.defines());
}

MediaPass::Frame PreviewRenderer::mediaFrame(const Camera& camera, const Settings& settings) const {
  const float diagonal = std::max(scene_->bounds.diagonal(), 1e-6f);
  const float aspect = static_cast<float>(settings.width) / static_cast<float>(settings.height);
  const glm::mat4 view = glm::lookAt(camera.position, camera.position + camera.forward, camera.up);
  const glm::mat4 proj = glm::perspective(camera.yfov, aspect, camera.znear, camera.zfar);
  // The same far and bias as the VPL maps are built with (render()), and the sphere a directional light's map covers.
  return {lambertOnly_,     camera,          glm::inverse(proj * view),     scene_->bounds.center(),
          diagonal,         0.51f * diagonal, 2.0f * diagonal,              settings.shadowBias * diagonal};
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

std::size_t previewFirstFrameBytes(const Settings& settings) {
  // The screen targets (Targets) measured 250-265 bytes a pixel at 640x480 with s = 1 and s = 2; the VPL maps as
  // visibilityFootprint counts them, for hemicubes (3 of a cube's 6 faces) of about settings.vplCount VPLs. Half as
  // much again for the lights' maps, the read-back and the smaller textures: the Cornell box at 640x480 created 120
  // MB of textures of a megabyte or more, and warming 160 MB left half the faults that 128 MB left.
  const double screen = 256.0 * settings.width * static_cast<double>(settings.height);
  const double face = vplCubeFaceSize(settings.shadowMapSize);
  const double maps = 2.0 * 3.0 * face * face * std::min(settings.vplCount, settings.previewRepresentatives);
  return static_cast<std::size_t>(1.5 * (screen + maps));
}

std::string previewFitProblem(const Scene& scene, std::size_t vplCount, const Settings& settings,
                              const GlLimits& limits) {
  std::ostringstream why;
  const int largest = std::min(limits.maxTextureSize, limits.maxFramebufferSize);
  if (settings.width > largest || settings.height > largest) {
    why << "image size " << settings.width << "x" << settings.height
        << " exceeds this GL context's largest render target " << largest << ": lower --size";
    return why.str();
  }
  // The compensation's tap buffers hold every mip level of the grid it runs on (ssbc_pass.h).
  const glm::ivec2 grid = indirectGridSize(settings.width, settings.height, settings.indirectDownscale);
  if (ssbcCompensates(settings)) {
    const int tapTexels = ssbcTapLevelBases(grid.x, grid.y).back();
    if (tapTexels > limits.maxTextureBufferSize) {
      why << "the compensation at " << grid.x << "x" << grid.y << " needs buffer textures of " << tapTexels
          << " texels, over this GL context's " << limits.maxTextureBufferSize
          << ": lower --size, raise --indirect-downscale, or --ssbc-steps 0";
      return why.str();
    }
  }
  const VisibilityMethod visibility = resolveVisibility(settings.visibility, scene.triangles.size(), vplCount);
  VisibilityFootprint vplMaps = visibilityFootprint(visibility, static_cast<int>(vplCount), settings, limits);
  if (!vplMaps.problem.empty()) return vplMaps.problem;
  // The screen targets (Targets: G-buffer, interleaved and merged results, compensation mips and rings), counted as 40
  // RGBA32F-sized texels per pixel, an upper bound, and as many again per texel of the indirect light's own grid.
  const double gridTexels = static_cast<double>(grid.x) * grid.y;
  const double targetBytes =
      40.0 * 16.0 *
      (settings.width * static_cast<double>(settings.height) + (settings.indirectDownscale > 1 ? gridTexels : 0.0));
  // The lights' maps: an R32F cube per area-light group and per point or spot light, an R32F square per directional.
  int cubes = scene.emissiveTriangles.empty() ? 0 : kMaxAreaGroups, squares = 0;
  for (const PunctualLight& l : scene.punctualLights) (l.isDirectional() ? squares : cubes) += 1;
  const LightMapSizes lightMaps = LightMapSizes::of(settings);
  const double lightBytes =
      4.0 * (6.0 * cubes * lightMaps.punctualFace * lightMaps.punctualFace +
             static_cast<double>(squares) * lightMaps.directional * lightMaps.directional);
  // A density grid is an R32F 3D texture of its stored voxels: 4 bytes each. Where no texture holds it, a NanoVDB grid
  // of the 8^3 leaves with smoke and the tree's nodes (DensityGridsGpu) takes that for a plume whose box is mostly
  // empty, and up to about twice that for a dense one (0.45 MiB for cornell-smoke's 0.22 MiB of voxels); counted here
  // at the texture's size.
  double gridBytes = 0.0;
  for (const Medium& m : scene.media) {
    if (!m.heterogeneous() || m.isVacuum()) continue;
    const glm::ivec3 size = m.density->size;
    gridBytes += 4.0 * size.x * size.y * static_cast<double>(size.z);
  }
  // The direct light's blocker searches (DirectLightPass): an RGBA32F texel per k x k pixel block and area-light group.
  const double searchBytes =
      scene.emissiveTriangles.empty()
          ? 0.0
          : 16.0 * kMaxAreaGroups * std::ceil(static_cast<double>(settings.width) / settings.interleave) *
                std::ceil(static_cast<double>(settings.height) / settings.interleave);
  const double total = vplMaps.bytes + targetBytes + searchBytes + lightBytes + gridBytes;
  if (total > limits.memoryBytes && gridBytes > 0.5 * total) {
    why << "the scene's density grids need up to " << formatBytes(gridBytes) << " of GPU memory: the preview needs "
        << formatBytes(total) << ", over the " << formatBytes(limits.memoryBytes) << " it allows itself here (half the "
        << limits.memorySource << "); the grids are the cause: use coarser grids, or vplab render";
    return why.str();
  }
  // When the lights' own shadow maps are most of it, no VPL or image flag helps: say that the lights are the cause
  // (10,000 point lights need 10,000 cubes).
  if (total > limits.memoryBytes && lightBytes > 0.5 * total) {
    why << "the scene's " << cubes + squares << " lights need " << formatBytes(lightBytes)
        << " of light shadow maps (one R32F cube of 6x" << lightMaps.punctualFace << "^2 per point or spot light, a "
        << lightMaps.directional << "^2 map per directional light): the preview needs " << formatBytes(total)
        << ", over the " << formatBytes(limits.memoryBytes) << " it allows itself here (half the "
        << limits.memorySource << "); the lights are the cause: use fewer lights, or vplab render, which has no "
        << "light shadow maps";
    return why.str();
  }
  if (total > limits.memoryBytes)
    why << vplMaps.what << " need " << formatBytes(vplMaps.bytes) << "; with the " << settings.width << "x"
        << settings.height << " targets and up to " << cubes + squares << " light shadow map(s) the preview needs "
        << formatBytes(total) << ", over the " << formatBytes(limits.memoryBytes) << " it allows itself here (half the "
        << limits.memorySource << "): lower --vpl-count, --size or "
        << (visibility == VisibilityMethod::Ism ? "--ism-tile-size"
                                                         : "--shadow-map-size, or use --visibility ism");
  return why.str();
}

PreviewTimings PreviewRenderer::render(const Scene& scene, const VplSet& vpls, const Settings& settings,
                                       const Camera& camera, double budgetMs) {
  auto frameStart = std::chrono::steady_clock::now();
  requireValidSettings(settings);
  if (limits_.maxTextureSize == 0) limits_ = queryGlLimits();
  if (std::string problem = previewFitProblem(scene, vpls.vpls.size(), settings, limits_); !problem.empty())
    throw std::runtime_error(problem);
  if (std::string problem = mediaFitProblem(scene); !problem.empty()) throw std::runtime_error(problem);
  PreviewTimings t;
  if (&scene != scene_ || scene.id != sceneId_ || sceneDirty_ || !glScene_) {
    glScene_ = std::make_unique<GlScene>(scene);
    scene_ = &scene;
    sceneId_ = scene.id;
    // The same test as evaluateBrdf's Lambert fast path (metallic and specular are per material, never textured).
    lambertOnly_ = std::all_of(scene.materials.begin(), scene.materials.end(),
                               [](const Material& m) { return m.metallic <= 0.0f && m.specular <= 0.0f; });
    uploadedMedia_.clear();
    sceneDirty_ = false;
    haveFrame_ = false;
    shadowsValid_ = false;
    vplsDirty_ = true;
  }
  if (&vpls != vplSet_ || vpls.id != vplSetId_) vplsDirty_ = true;
  vplSet_ = &vpls;
  vplSetId_ = vpls.id;
  ensureTargets(settings.width, settings.height);
  Targets& tg = *targets_;
  tg.ensureDownscale(settings.indirectDownscale);
  ScreenGrid& grid = tg.indirectGrid();
  const bool ownGrid = &grid != &tg.full;

  // Which passes are stale: what renderer/invalidation.h says the settings and camera changes since the last frame
  // affect (the offline result aside), and what depends on the scene, lights and VPLs this renderer was handed.
  Staleness stale = staleAfterSettingsChange(lastSettings_, settings, Method::Reference);
  if (!haveFrame_ || !sameCamera(camera, lastCamera_)) stale |= staleAfterCameraMove();
  if (!shadowsValid_ || lightsDirty_) stale.lightShadowMaps = true;
  // The media are compared with those uploaded, so that an edit in place (the editor's) needs no call: what they
  // change is what renderer/invalidation.h says (the direct light's transmittance and all the VPLs do).
  if (const Staleness mediaEdit = staleAfterMediumEdit(uploadedMedia_, scene.media);
      mediaEdit.anyPreview() || !haveFrame_ || settings.previewGridInBuffer != lastSettings_.previewGridInBuffer) {
    media_.upload(scene, settings.clampBound, settings.previewGridInBuffer);
    direct_.useMedia(media_.layout());
    uploadedMedia_ = scene.media;
    stale |= mediaEdit;
  }
  lightsDirty_ = false;
  const VisibilityMethod visibility = resolveVisibility(settings.visibility, scene.triangles.size(), vpls.vpls.size());
  if (visibility != visibilityMethod_ || media_.layout() != gatherMedia_) {
    useVisibility(visibility, media_.layout());
    vplsDirty_ = true;
  }
  // The compensation factors depend on the bound (a change of which the gather's staleness covers).
  if (media_.active() && settings.clampBound != media_.uploadedBound())
    media_.upload(scene, settings.clampBound, settings.previewGridInBuffer);
  if (media_.active()) media_.bind();
  if (!shadowsValid_) vplVisibility_->resetScene();
  // The renderer does not generate VPLs: a new or edited set is uploaded and gathered again. Its maps depend on the
  // casters (position, and orientation for paraboloid tiles) and the map sizes only, which the technique compares:
  // flux, radius or material edits just re-upload the VPLs.
  const bool vplDataChanged = vplsDirty_ || stale.vpls;
  stale.vpls = false;
  // The gather's order (Lambert VPLs first, gather_pass.h) is also the maps'.
  int lambertVpls = 0;
  const std::vector<uint32_t> order = gatherOrder(scene, vpls, &lambertVpls);
  std::vector<VplCaster> casters(vpls.vpls.size());
  // A medium VPL lights every direction; a technique that orients its map (a paraboloid) faces the way its light
  // travelled, where the phase function of a forward-scattering medium sends most of it.
  for (std::size_t i = 0; i < casters.size(); ++i) {
    const Vpl& v = vpls.vpls[order[i]];
    casters[i] = {v.position, v.inMedium ? -v.incoming : v.geometricNormal, v.inMedium};
  }
  if (stale.vplShadowMaps || vplDataChanged) stale.vplShadowMaps = vplVisibility_->stale(casters, settings);
  stale.gather |= vplDataChanged;
  stale = stale.propagated();

  // What this call found stale joins what earlier calls left undone (a budget cut them short); the passes then run in
  // order from the first pending one until the budget is spent.
  const bool jobRunning = pending_.any();
  if (stale.gbuffer) gbufferSlices_.restart();
  pending_.gbuffer |= stale.gbuffer;
  // Maps cut short by a budget start over when the lights or their samples changed again.
  if (stale.lightShadowMaps) direct_.restartMaps();
  pending_.directMaps |= stale.lightShadowMaps;
  pending_.vplMaps |= stale.vplShadowMaps;
  // A pass sliced over earlier calls starts over when what it reads changed again.
  if (stale.direct) direct_.restartDraw();
  pending_.direct |= stale.direct;
  if (stale.gather) gather_.restart();
  if (stale.direct || stale.gather) {
    media_.restartDraw();
    mergeSlices_.restart();
  }
  if (stale.ssbc) ssbcSlices_.restart();
  pending_.gather |= stale.gather;
  pending_.mediaLights |= media_.active() && stale.direct;
  pending_.mediaVpls |= media_.active() && stale.gather;
  pending_.merge |= stale.direct || stale.gather;
  pending_.ssbc |= stale.ssbc;
  if (!jobRunning) jobDone_ = 0;
  jobTotal_ = jobDone_ + pending_.count();
  haveFrame_ = true;
  lastCamera_ = camera;
  lastSettings_ = settings;
  // Whether this call has the gather to do (the merge's time is counted in it, else in the direct pass).
  const bool gatherPending = pending_.gather;
  // A pass runs only while no earlier pass of this call has spent the budget; each clears its pending flag.
  bool outOfBudget = false;
  auto finished = [&](bool& flag) {
    flag = false;
    ++jobDone_;
    outOfBudget = msSince(frameStart) > budgetMs;
  };
  // The end of a pass that a budget can cut short: done, it counts itself and clears its flag; cut short, the passes
  // after it wait for the next call.
  auto ended = [&](bool done, int& counter, bool& flag) {
    if (!done) {
      outOfBudget = true;
      return;
    }
    ++counter;
    finished(flag);
  };
  // For the passes that stop between slices: the time spent is known only once the GPU has made the slice.
  std::function<bool()> outOfTime;
  if (std::isfinite(budgetMs))
    outOfTime = [&] {
      glFinish();
      return msSince(frameStart) > budgetMs;
    };

  float diagonal = std::max(scene.bounds.diagonal(), 1e-6f);
  float far = 2.0f * diagonal;
  float bias = settings.shadowBias * diagonal;
  // The bounding sphere a directional light's map covers, a little larger so that no surface lies on its rim.
  const float sceneRadius = 0.51f * diagonal;
  glm::mat4 view = glm::lookAt(camera.position, camera.position + camera.forward, camera.up);
  float aspect = static_cast<float>(settings.width) / static_cast<float>(settings.height);
  glDisable(GL_BLEND);
  glDisable(GL_DEPTH_TEST);

  // Pass 1: G-buffer, in bands of rows when a budget is given (each band clears and rasterises its own rows).
  if (pending_.gbuffer) {
    gbufferSlices_.begin(outOfTime);
    t.gbufferMs = timed(timer_, t.gbufferWallMs, [&] {
      GlFramebuffer& gbuffer = tg.full.g.framebuffer;
      gbuffer.bind(tg.width, tg.height);
      // Reversed depth: depth 1 at the near plane falling as 1/z to 0 at infinity, in a float buffer, resolves
      // surfaces a millimetre apart at any distance. A glTF camera's znear of 5 cm with GL's usual depth left 3 mm
      // steps at 1.6 m, and a top plate lost to the part 5 mm beneath it (docs/methods.md "Direct light in the preview").
      glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
      glDepthFunc(GL_GREATER);
      glDisable(GL_CULL_FACE);
      glScene_->bind();
      ShaderProgram& surfaces = glScene_->textured() ? gbufferTextured_.get() : gbufferUntextured_.get();
      surfaces.set("uViewProj", reversedDepthProjection(camera.yfov, aspect, camera.znear) * view);
      surfaces.set("uCameraPosition", camera.position);
      gbufferSlices_.bands(glm::ivec4(0, 0, tg.width, tg.height), [&] {
        gbuffer.clearDepth(0.0f);
        glEnable(GL_DEPTH_TEST);
        surfaces.use();
        vao_.bind();
        drawProceduralTriangles(3 * glScene_->triangleCount());
        // Then the background, where the depth is still the clear's (preview/gbuffer_background.frag.glsl).
        glDepthFunc(GL_EQUAL);
        glDepthMask(GL_FALSE);
        drawFullscreen(gbufferBackground_, vao_);
        glDepthMask(GL_TRUE);
        glDepthFunc(GL_GREATER);
        glDisable(GL_DEPTH_TEST);
      });
      glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
      tg.full.gbufferDerivedCurrent = false;
      if (ownGrid) {
        // The indirect light's grid takes the G-buffer's texels at its representatives: once every band is drawn.
        tg.full.g.bind();
        grid.g.framebuffer.bind(grid.width, grid.height);
        gridGbuffer_->set("uDownscale", tg.downscale);
        gbufferSlices_.bands(glm::ivec4(0, 0, grid.width, grid.height),
                             [&] { drawFullscreen(gridGbuffer_.get(), vao_); });
        grid.gbufferDerivedCurrent = false;
      }
    });
    ended(gbufferSlices_.end(), counters_.gbuffer, pending_.gbuffer);
  }

  // The lights' shadow maps, a cube face at a time when a budget is given.
  if (pending_.directMaps && !outOfBudget) {
    bool built = false;
    // Drawn on the CPU and uploaded (distance_raster.h): the wall time is the pass's time.
    timed(timer_, t.directShadowWallMs, [&] { built = direct_.renderMaps(scene, settings, sceneRadius, outOfTime); });
    t.directShadowMs = t.directShadowWallMs;
    ended(built, counters_.directShadowMaps, pending_.directMaps);
  }

  if (vplDataChanged) gather_.upload(scene, vpls, order, lambertVpls);
  vplsDirty_ = false;
  // Pass 3: the VPLs' visibility maps. A technique that builds them in slices stops when the budget is spent and goes
  // on in the next call.
  if (pending_.vplMaps && !outOfBudget) {
    bool built = false;
    // Drawn (cube maps) or splatted (ISM tiles) on the CPU and uploaded: the wall time is the pass's time.
    timed(timer_, t.vplShadowWallMs,
          [&] { built = vplVisibility_->update(*glScene_, scene, casters, settings, far, outOfTime); });
    t.vplShadowMs = t.vplShadowWallMs;
    ended(built, counters_.vplShadowMaps, pending_.vplMaps);
  }
  shadowsValid_ = true;

  tg.full.ensureRaw(settings.interleave, true, direct_.hasExactLights());
  if (ownGrid) grid.ensureRaw(settings.interleave, false, false);

  // Pass 2: direct light, interleaved over the light samples, draw by draw (in bands of rows) when a budget is given.
  if (pending_.direct && !outOfBudget) {
    bool drawn = false;
    t.directMs = timed(timer_, t.directWallMs, [&] {
      tg.full.g.bind();
      drawn = direct_.draw(lambertOnly_, camera, scene.bounds.center(), sceneRadius, *tg.full.directRaw,
                           tg.full.interleaved(), tg.full.punctualDirect.get(), vao_, outOfTime);
    });
    tg.directMergeStale = true;
    ended(drawn, counters_.direct, pending_.direct);
  }

  // Pass 4: VPL gather with G_b / VSL and interleaving (the de-interleave follows), draw by draw when a budget is
  // given.
  if (pending_.gather && !outOfBudget) {
    bool gathered = false;
    t.gatherMs = timed(timer_, t.gatherWallMs, [&] {
      grid.g.bind();
      gathered = gather_.draw(lambertOnly_, camera, settings, far, bias, *vplVisibility_, *grid.indirectRaw,
                              grid.interleaved(), vao_, outOfTime);
    });
    ended(gathered, counters_.gather, pending_.gather);
  }

  // Geometry-aware de-interleave of the direct light and the gather together into I0 (deinterleave.frag.glsl): the
  // merge is linear and its weights depend on the G-buffer only, so one merge serves both. On a grid of its own the
  // gather is merged there and I0 takes the merged direct light at the grid's representatives. Its time is counted in
  // the gather pass (in the direct pass when only that one ran).
  // The media's scattering along camera rays, on the indirect light's grid: after the lights' and the VPLs' maps and
  // the passes that use them.
  // Sliced like the surface passes.
  if (pending_.media() && !pending_.directMaps && !pending_.vplMaps && !pending_.direct && !pending_.gather &&
      !outOfBudget) {
    bool drawn = false;
    t.mediaMs = timed(timer_, t.mediaWallMs, [&] {
      grid.g.bind();
      drawn = media_.draw(mediaFrame(camera, settings), settings, grid.interleaved(), direct_, gather_,
                          *vplVisibility_, vao_, pending_.mediaLights, pending_.mediaVpls, outOfTime);
    });
    if (drawn) pending_.mediaLights = false;
    ended(drawn, counters_.media, pending_.mediaVpls);
  }

  // The merge reads k x k neighbours of the interleaved results: it starts once every band of them is drawn. Each of
  // its draws is a slice (in bands of rows) of its own.
  if (pending_.merge && !pending_.direct && !pending_.gather && !outOfBudget) {
    double wallMs = 0.0;
    mergeSlices_.begin(outOfTime);
    double gpuMs = timed(timer_, wallMs, [&] {
      if (!ownGrid) {
        mergeInterleaved(tg.full, glm::vec2(1.0f), tg.full.results().i0.framebuffer, mergeSlices_);
        return;
      }
      // Whether the direct light is merged again is taken when the merge starts, since the merge itself clears it.
      if (mergeSlices_.starting()) mergeDirect_ = tg.directMergeStale;
      if (mergeDirect_) {
        // Punctual lights alone need no merge: their light is per pixel already.
        if (direct_.hasAreaSamples())
          mergeInterleaved(tg.full, glm::vec2(1.0f, 0.0f), tg.direct.framebuffer, mergeSlices_);
        else if (tg.full.punctualDirect)
          mergeSlices_.step([&] { tg.direct.texture.copyFrom(tg.full.punctualDirect->texture); });
        else
          mergeSlices_.step([&] { tg.direct.framebuffer.clearColor(0, glm::vec4(0.0f)); });
        mergeSlices_.step([&] { tg.directMergeStale = false; });
      }
      mergeInterleaved(grid, glm::vec2(0.0f, 1.0f), grid.indirect().framebuffer, mergeSlices_);
      tg.full.g.bind();
      tg.direct.texture.bind(unit(TextureUnit::PassInput0));
      grid.indirect().texture.bind(unit(TextureUnit::PassInput1));
      grid.results().i0.framebuffer.bind(grid.width, grid.height);
      gridInput_->set("uDownscale", tg.downscale);
      mergeSlices_.bands(glm::ivec4(0, 0, grid.width, grid.height), [&] { drawFullscreen(gridInput_.get(), vao_); });
    });
    t.deinterleaveMs = gpuMs;
    (gatherPending ? t.gatherMs : t.directMs) += gpuMs;
    (gatherPending ? t.gatherWallMs : t.directWallMs) += wallMs;
    if (mergeSlices_.end())
      finished(pending_.merge);
    else
      outOfBudget = true;
  }

  // Pass 5: R1 = T_r(I0) (I0 = direct + indirect, merged by the de-interleave), R2 = T_r(R1), final = Le + I0 + R1
  // + R2 (the final composition reads R1 and R2 itself; readLinear(PreviewOutput::Residual) sums them on demand).
  // The compensation and the compositions after it, a draw (in bands of rows) at a time when a budget is given.
  if (pending_.ssbc && !pending_.merge && !pending_.media() && !outOfBudget) {
    ssbcSlices_.begin(outOfTime);
    t.ssbcMs = timed(timer_, t.ssbcWallMs, [&] {
      grid.g.bind();
      ScreenGrid::IndirectResults& results = grid.results();
      residualSteps_ = ssbc_.run(
          lambertOnly_, camera, settings,
          {grid.g.position, grid.g.normal, grid.gbufferDerivedCurrent, results.i0, results.r1, results.r2}, vao_,
          ssbcSlices_);
      if (ownGrid) {
        upsample(glm::vec4(1.0f, 1.0f, residualSteps_ >= 1, residualSteps_ >= 2), tg.linear.framebuffer, ssbcSlices_);
      } else {
        tg.linear.framebuffer.bind(tg.width, tg.height);
        tg.full.g.bind();
        tg.full.results().i0.texture.bind(unit(TextureUnit::PassInput0));
        tg.full.results().r1.texture.bind(unit(TextureUnit::PassInput2));
        tg.full.results().r2.texture.bind(unit(TextureUnit::PassInput3));
        compose_->set("uResidualSteps", residualSteps_);
        ssbcSlices_.bands(glm::ivec4(0, 0, tg.width, tg.height), [&] { drawFullscreen(compose_.get(), vao_); });
      }
      // Through media: the surfaces' image attenuated along the camera rays, plus the light scattered into them.
      if (media_.active()) {
        tg.full.g.bind();
        // With compensation on (ssbcSteps > 0), the media's approximate bias compensation (media_pass.h) too.
        const float compensate = settings.ssbcSteps > 0 ? 1.0f : 0.0f;
        media_.compose(mediaFrame(camera, settings), tg.linear.texture, glm::vec4(1.0f, 1.0f, 1.0f, compensate),
                       tg.width, tg.height, tg.linear.framebuffer, vao_, ssbcSlices_);
      }
    });
    ended(ssbcSlices_.end(), counters_.ssbc, pending_.ssbc);
  }

  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  checkGlError("PreviewRenderer::render");

  if (gatherPending && !pending_.gather)
    t.gatherEvaluations = static_cast<double>(grid.width) * grid.height *
                          static_cast<double>(vpls.vpls.size()) /
                          static_cast<double>(settings.interleave * settings.interleave);
  t.frameWallMs = msSince(frameStart);
  t.complete = !pending_.any();
  t.progress = jobTotal_ > 0 ? static_cast<float>(jobDone_) / static_cast<float>(jobTotal_) : 1.0f;
  return t;
}

void PreviewRenderer::mergeInterleaved(ScreenGrid& grid, glm::vec2 weights, GlFramebuffer& out, PassSlices& slices) {
  const int k = grid.rawInterleave;
  // Rows, then columns (separable: 2k neighbours per pixel instead of k^2).
  grid.rows.framebuffer.bind(grid.width, grid.height);
  grid.g.bind();
  // A component with weight 0 is not read at all: llvmpipe would fetch it at every tap, whatever its weight (the
  // direct light's merge at 640x480, s = 2: 9.0-9.3 -> 5.9-6.1 ms). A grid without a direct light of its own merges
  // the gather alone (weights.x = 0); its gather stands in for the direct light's input otherwise, so that nothing
  // undefined is bound.
  Target& direct = grid.directRaw ? *grid.directRaw : *grid.indirectRaw;
  const bool both = weights.x != 0.0f && weights.y != 0.0f, directAlone = !both && weights.x != 0.0f;
  ShaderProgram& rows = both ? deinterleaveRows_.get() : deinterleaveRowsOneInput_.get();
  if (both) {
    direct.texture.bind(unit(TextureUnit::PassInput0));
    grid.indirectRaw->texture.bind(unit(TextureUnit::PassInput1));
    rows.set("uWeights", weights);
  } else {
    (directAlone ? direct : *grid.indirectRaw).texture.bind(unit(TextureUnit::PassInput0));
    rows.set("uWeight", directAlone ? weights.x : weights.y);
  }
  rows.set("uInterleave", k);
  rows.set("uBlockSize", glm::ivec2(grid.blockWidth, grid.blockHeight));
  slices.bands(glm::ivec4(0, 0, grid.width, grid.height), [&] { drawFullscreen(rows, vao_); });
  // The columns read the row sums of k neighbours: every band of them is drawn by now.
  out.bind(grid.width, grid.height);
  grid.rows.texture.bind(unit(TextureUnit::PassInput0));
  (grid.punctualDirect ? *grid.punctualDirect : grid.rows).texture.bind(unit(TextureUnit::PassInput1));
  deinterleaveColumns_.set("uPunctualWeight", grid.punctualDirect ? weights.x : 0.0f);
  deinterleaveColumns_.set("uInterleave", k);
  slices.bands(glm::ivec4(0, 0, grid.width, grid.height), [&] { drawFullscreen(deinterleaveColumns_, vao_); });
}

void PreviewRenderer::upsample(glm::vec4 terms, GlFramebuffer& out, PassSlices& slices) {
  Targets& tg = *targets_;
  ScreenGrid& grid = *tg.downscaled;
  grid.g.bind();
  grid.indirect().texture.bind(unit(TextureUnit::PassInput1));
  grid.results().r1.texture.bind(unit(TextureUnit::PassInput2));
  grid.results().r2.texture.bind(unit(TextureUnit::PassInput3));
  grid.results().light.framebuffer.bind(grid.width, grid.height);
  gridLight_->set("uTerms", terms);
  slices.bands(glm::ivec4(0, 0, grid.width, grid.height), [&] { drawFullscreen(gridLight_.get(), vao_); });
  // The upsample reads the grid's light around each pixel's representative: every band of it is drawn by now.
  tg.full.g.bind();
  tg.direct.texture.bind(unit(TextureUnit::PassInput0));
  grid.results().light.texture.bind(unit(TextureUnit::PassInput1));
  grid.results().blockPlane.bind(unit(TextureUnit::PassInput2));
  grid.g.position.bind(unit(TextureUnit::PassInput4));
  grid.g.mergeKey.bind(unit(TextureUnit::PassInput5));
  out.bind(tg.width, tg.height);
  upsample_->set("uDownscale", tg.downscale);
  upsample_->set("uTerms", terms);
  slices.bands(glm::ivec4(0, 0, tg.width, tg.height), [&] { drawFullscreen(upsample_.get(), vao_); });
}

void PreviewRenderer::throughMedia(Target& target, glm::vec4 weights) {
  if (!media_.active() || !haveFrame_) return;
  targets_->full.g.bind();
  PassSlices whole;
  media_.compose(mediaFrame(lastCamera_, lastSettings_), target.texture, weights, targets_->width, targets_->height,
                 target.framebuffer, vao_, whole);
}

Image PreviewRenderer::readLinear(PreviewOutput which) {
  if (!targets_) return {};
  Targets& tg = *targets_;
  if (which == PreviewOutput::Scattered) {
    if (!media_.active()) return Image(tg.width, tg.height);
    tg.full.indirect().texture.copyFrom(tg.linear.texture);
    throughMedia(tg.full.indirect(), glm::vec4(0.0f, 1.0f, 1.0f, lastSettings_.ssbcSteps > 0 ? 1.0f : 0.0f));
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return readFramebuffer(tg.full.indirect().framebuffer, 0, tg.width, tg.height);
  }
  if (tg.downscaled && (which == PreviewOutput::Residual || which == PreviewOutput::Indirect)) {
    // Upsampled from the indirect light's grid on demand.
    const bool residual = which == PreviewOutput::Residual;
    PassSlices whole;
    upsample(glm::vec4(0.0f, !residual, residual && residualSteps_ >= 1, residual && residualSteps_ >= 2),
             tg.full.indirect().framebuffer, whole);
    throughMedia(tg.full.indirect(), residual ? glm::vec4(1.0f, 0.0f, 0.0f, 0.0f) : glm::vec4(1.0f, 0.0f, 1.0f, 0.0f));
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return readFramebuffer(tg.full.indirect().framebuffer, 0, tg.width, tg.height);
  }
  if (which == PreviewOutput::Residual) {
    // R1 + R2: the final composition adds them itself, so the sum is formed only when asked for.
    Image residual(tg.width, tg.height);
    for (int step = 0; step < residualSteps_; ++step) {
      Target& result = step == 0 ? tg.full.results().r1 : tg.full.results().r2;
      Image r = readFramebuffer(result.framebuffer, 0, tg.width, tg.height);
      for (std::size_t i = 0; i < residual.size(); ++i) residual.pixels[i] += r.pixels[i];
    }
    return residual;
  }
  if (which == PreviewOutput::Direct || which == PreviewOutput::Indirect) {
    // A frame merges only their sum I0; one component is merged from the interleaved passes' results on demand.
    if (!tg.full.directRaw) return {};
    const bool direct = which == PreviewOutput::Direct;
    Target& out = direct ? tg.direct : tg.full.indirect();
    PassSlices whole;
    mergeInterleaved(tg.full, direct ? glm::vec2(1.0f, 0.0f) : glm::vec2(0.0f, 1.0f), out.framebuffer, whole);
    throughMedia(out, direct ? glm::vec4(1.0f, 1.0f, 0.0f, 0.0f) : glm::vec4(1.0f, 0.0f, 1.0f, 0.0f));
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return readFramebuffer(out.framebuffer, 0, tg.width, tg.height);
  }
  return readFramebuffer(tg.linear.framebuffer, 0, tg.width, tg.height);
}

}  // namespace vplab
