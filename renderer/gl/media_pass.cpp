#include "renderer/gl/media_pass.h"

#include <glad/gl.h>

#include <algorithm>

#include "renderer/gl/light_table.h"
#include "renderer/gl/texture_units.h"

namespace vplab {

namespace {
// std140 layout of the Media block of shaders/common/medium.glsl.
struct MediumGpu {
  glm::vec4 sigmaT, sigmaS;
  glm::mat4 boxFromWorld;
};
struct MediaTableGpu {
  MediumGpu media[kPreviewMaxMedia];
};

std::string mediaDefine(int count) {
  return "PREVIEW_MEDIA " + std::to_string(count);
}
}  // namespace

std::string mediaFitProblem(const Scene& scene) {
  const auto drawn =
      std::count_if(scene.media.begin(), scene.media.end(), [](const Medium& m) { return !m.isVacuum(); });
  if (drawn <= kPreviewMaxMedia) return {};
  return "the scene holds " + std::to_string(drawn) + " media; the preview draws at most " +
         std::to_string(kPreviewMaxMedia) + ": join boxes, or use vplab render";
}

MediaPass::MediaPass() : merge_({"preview/fullscreen.vert.glsl", "preview/media_merge.frag.glsl"}) {}

void MediaPass::upload(const Scene& scene) {
  MediaTableGpu gpu{};
  count_ = 0;
  for (const Medium& m : scene.media) {
    // Media that neither absorb nor scatter change nothing (mediumIntervals leaves them out too).
    if (m.isVacuum() || count_ == kPreviewMaxMedia) continue;
    gpu.media[count_++] = {glm::vec4(m.sigmaT(), m.fillsSpace ? 1.0f : 0.0f), glm::vec4(m.sigmaS, m.g), m.boxFromWorld};
  }
  table_.assign(&gpu, sizeof(gpu));
  if (count_ > 0 && count_ != composeCount_) {
    compose_ = std::make_unique<ShaderProgram>(
        std::vector<std::string>{"preview/fullscreen.vert.glsl", "preview/media_compose.frag.glsl"},
        std::vector<std::string>{mediaDefine(count_)});
    composeCount_ = count_;
  }
}

void MediaPass::bind() const {
  table_.bindUniform(binding(BufferBinding::Media));
}

void MediaPass::useGatherDefines(const std::vector<std::string>& gatherDefines) {
  vpls_ = std::make_unique<BrdfVariants>("preview/media_vpls.frag.glsl", gatherDefines);
}

void MediaPass::ensureTargets(const InterleavedLayout& layout) {
  const int rawWidth = layout.blockWidth * layout.k, rawHeight = layout.blockHeight * layout.k;
  if (rawWidth != rawWidth_ || rawHeight != rawHeight_) {
    lightsRaw_ = std::make_unique<Target>(rawWidth, rawHeight);
    vplsRaw_ = std::make_unique<Target>(rawWidth, rawHeight);
    rawWidth_ = rawWidth;
    rawHeight_ = rawHeight;
  }
  if (layout.width != gridWidth_ || layout.height != gridHeight_) {
    merged_ = std::make_unique<Target>(layout.width, layout.height);
    mergedVpls_ = std::make_unique<GlTexture>(layout.width, layout.height, TextureFormat::Rgba32F);
    merged_->texture.setLinearFiltering(true);
    merged_->texture.setRepeat(false);
    mergedVpls_->setLinearFiltering(true);
    mergedVpls_->setRepeat(false);
    merged_->framebuffer.attachColor(1, *mergedVpls_);
    merged_->framebuffer.finalize(2);
    gridWidth_ = layout.width;
    gridHeight_ = layout.height;
  }
}

void MediaPass::draw(const Frame& frame, const Settings& settings, const InterleavedLayout& layout,
                     const DirectLightPass& direct, const VplGatherPass& gather, const VplVisibility& visibility,
                     const GlVertexArray& vao) {
  ensureTargets(layout);
  const int k = layout.k, k2 = k * k;
  auto common = [&](ShaderProgram& p) {
    p.set("uCameraPosition", frame.camera.position);
    p.set("uInvViewProj", frame.invViewProj);
    p.set("uSceneDiagonal", frame.sceneDiagonal);
    p.set("uInterleave", k);
    p.set("uImageSize", glm::ivec2(layout.width, layout.height));
  };

  // The lights' single scattering: every subset draws every punctual and directional light and its share of the area
  // samples, from the direct pass's table, in ranges of one uniform block.
  const DirectLightPass::TableView table = direct.bindTable();
  if (!lights_ || lightsLayoutCapacity_ != table.layout.capacity || lightsCount_ != count_) {
    lights_ = std::make_unique<ShaderProgram>(
        std::vector<std::string>{"preview/fullscreen.vert.glsl", "preview/media_lights.frag.glsl"},
        std::vector<std::string>{uniformTableDefine("DIRECT_UBO_LIGHTS", table.layout), mediaDefine(count_)});
    lightsLayoutCapacity_ = table.layout.capacity;
    lightsCount_ = count_;
  }
  ShaderProgram& lights = *lights_;
  common(lights);
  lights.set("uMediaSteps", kMediaLightSteps);
  lights.set("uLightShadowTexel", 2.0f / static_cast<float>(kLightShadowFaceSize));
  lights.set("uSceneCentre", frame.sceneCentre);
  lights.set("uSceneRadius", frame.sceneRadius);
  lights.set("uDirectionalShadowTexel", 2.0f * frame.sceneRadius / static_cast<float>(kDirectionalShadowSize));
  lights.set("uPunctualEnd", table.punctualEnd);
  lightsRaw_->framebuffer.bind(rawWidth_, rawHeight_);
  lightsRaw_->framebuffer.clearColor(0, glm::vec4(0.0f));
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE);
  const int step =
      std::max(table.layout.alignment, table.layout.capacity / table.layout.alignment * table.layout.alignment);
  for (int base = 0; base < table.count; base += step) {
    const int end = std::min(table.count, base + step);
    table.buffer->bindUniformRange(binding(BufferBinding::DirectLights),
                                   static_cast<std::size_t>(base) * table.layout.elementBytes,
                                   static_cast<std::size_t>(end - base) * table.layout.elementBytes);
    lights.set("uUboBase", base);
    lights.set("uLightBegin", base);
    lights.set("uLightEnd", end);
    lights.set("uAreaEnd", std::min(end, table.areaEnd));
    for (int subset = 0; subset < k2; ++subset) {
      const int sx = subset % k, sy = subset / k;
      const glm::ivec2 origin(sx * layout.blockWidth, sy * layout.blockHeight);
      glViewport(origin.x, origin.y, layout.blockWidth, layout.blockHeight);
      lights.set("uSubsetXY", glm::ivec2(sx, sy));
      lights.set("uBlockOrigin", origin);
      // The first area sample of this subset (index = subset mod k^2) from `base` on.
      lights.set("uAreaFirst", base + ((subset - base % k2) % k2 + k2) % k2);
      drawFullscreen(lights, vao);
    }
  }
  glDisable(GL_BLEND);

  // The VPLs' in-scattering, with the gather's table and maps.
  ShaderProgram& vpls = (*vpls_)[frame.lambertOnly];
  common(vpls);
  vpls.set("uClampBound", settings.clampBound);
  vpls.set("uShadowFar", frame.far);
  vpls.set("uShadowBias", frame.bias);
  gather.drawTable(vpls, visibility, *vplsRaw_, layout, vao);

  // The merge of the k x k subsets, both results at once.
  merged_->framebuffer.bind(layout.width, layout.height);
  lightsRaw_->texture.bind(unit(TextureUnit::PassInput0));
  vplsRaw_->texture.bind(unit(TextureUnit::PassInput1));
  merge_.set("uInterleave", k);
  merge_.set("uBlockSize", glm::ivec2(layout.blockWidth, layout.blockHeight));
  merge_.set("uImageSize", glm::ivec2(layout.width, layout.height));
  merge_.set("uCameraPosition", frame.camera.position);
  drawFullscreen(merge_, vao);
}

void MediaPass::compose(const Frame& frame, const GlTexture& surface, glm::vec3 weights, int width, int height,
                        GlFramebuffer& out, const GlVertexArray& vao) {
  if (!surfaceCopy_ || surfaceCopy_->texture.width() != width || surfaceCopy_->texture.height() != height)
    surfaceCopy_ = std::make_unique<Target>(width, height);
  surfaceCopy_->texture.copyFrom(surface);
  out.bind(width, height);
  surfaceCopy_->texture.bind(unit(TextureUnit::PassInput0));
  merged_->texture.bind(unit(TextureUnit::PassInput1));
  mergedVpls_->bind(unit(TextureUnit::PassInput2));
  ShaderProgram& compose = *compose_;
  compose.set("uCameraPosition", frame.camera.position);
  compose.set("uInvViewProj", frame.invViewProj);
  compose.set("uSceneDiagonal", frame.sceneDiagonal);
  compose.set("uWeights", weights);
  compose.set("uImageSize", glm::ivec2(width, height));
  drawFullscreen(compose, vao);
}

}  // namespace vplab
