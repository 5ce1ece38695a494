#include "renderer/gl/media_pass.h"

#include <glad/gl.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <stdexcept>

#include "renderer/gl/gl_limits.h"
#include "renderer/gl/light_table.h"
#include "renderer/gl/texture_units.h"
#include "renderer/scene/density_grid.h"

namespace vplab {

namespace {
// std140 layout of the Media block of shaders/common/medium.glsl.
struct MediumGpu {
  glm::vec4 sigmaT, sigmaS;
  glm::mat4 boxFromWorld;
  glm::vec4 compensation;
};
// A grid medium's density texture or NanoVDB grid (GlMediumGrid of common/medium.glsl).
struct MediumGridGpu {
  glm::mat4 textureFromWorld;  // the buffer's: index from world
  glm::vec4 size;              // xyz: texels along x, y, z (the buffer's: 1); w: densityScale
  glm::uvec4 bufferOffset;     // x: the byte offset of its NanoVDB grid in the buffer
};
struct MediaTableGpu {
  MediumGpu media[kPreviewMaxMedia];
  MediumGridGpu grids[kPreviewMaxDensityGrids];
};

// Index coordinates to the texture's: the value at index i sits at the centre of texel i - origin, so index p maps to
// (p - origin + 0.5) / size, and the texture's linear filtering is the grid's trilinear interpolation.
glm::mat4 textureFromIndex(const DensityGrid& grid) {
  const glm::vec3 size(grid.size);
  return glm::scale(glm::mat4(1.0f), 1.0f / size) * glm::translate(glm::mat4(1.0f), 0.5f - glm::vec3(grid.origin));
}
int max3dTextureSize() {
  int size = 0;
  glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &size);
  return size;
}

// A grid medium's row of the table for its grid's storage: texture coordinates (above), or index coordinates with
// one "texel" per voxel and the grid's place in the buffer, so that the march's step count is the voxels crossed
// either way.
MediumGridGpu gridRow(const Medium& m, DensityGridStorage storage, std::size_t bufferOffset) {
  if (storage == DensityGridStorage::Buffer)
    return {m.indexFromWorld, glm::vec4(1.0f, 1.0f, 1.0f, m.densityScale),
            glm::uvec4(static_cast<uint32_t>(bufferOffset), 0u, 0u, 0u)};
  return {textureFromIndex(*m.density) * m.indexFromWorld, glm::vec4(glm::vec3(m.density->size), m.densityScale),
          glm::uvec4(0u)};
}
}  // namespace

std::string mediaFitProblem(const Scene& scene) {
  const auto drawn =
      std::count_if(scene.media.begin(), scene.media.end(), [](const Medium& m) { return !m.isVacuum(); });
  if (drawn > kPreviewMaxMedia)
    return "the scene holds " + std::to_string(drawn) + " media; the preview draws at most " +
           std::to_string(kPreviewMaxMedia) + ": join boxes, or use vplab render";
  const auto grids = std::count_if(scene.media.begin(), scene.media.end(),
                                   [](const Medium& m) { return !m.isVacuum() && m.heterogeneous(); });
  if (grids > kPreviewMaxDensityGrids)
    return "the scene holds " + std::to_string(grids) + " media with density grids; the preview draws at most " +
           std::to_string(kPreviewMaxDensityGrids) + ": merge the grids into one, or use vplab render";
  return {};
}

int areaLightSteps(int areaSamples, int subsets) {
  if (areaSamples <= 0) return kMediaLightSteps;
  const int perPixel = std::max(1, areaSamples / std::max(1, subsets));
  return std::clamp((kMediaLightSteps + perPixel - 1) / perPixel, 1, kMediaLightSteps);
}

MediaPass::MediaPass() : merge_({"preview/fullscreen.vert.glsl", "preview/media_merge.frag.glsl"}) {}

float scatteringWeightedDensity(const DensityGrid& grid) {
  double sum = 0.0, squares = 0.0;
  for (float v : grid.values) {
    sum += v;
    squares += static_cast<double>(v) * v;
  }
  return sum > 0.0 ? static_cast<float>(squares / sum) : 0.0f;
}

glm::vec3 approximateCompensationFactor(const Medium& medium, float clampBound, float density) {
  if (!std::isfinite(clampBound) || !(clampBound > 0.0f)) return glm::vec3(0.0f);
  const double r = 1.0 / std::sqrt(static_cast<double>(clampBound)), b = clampBound;
  glm::vec3 c(0.0f);
  for (int i = 0; i < 3; ++i) {
    const double a = static_cast<double>(medium.sigmaT()[i]) * density, ar = a * r;
    // I0 = integral of e^(-a t), I2 = of t^2 e^(-a t), over [0, r]; by their series where a r is small (no
    // cancellation).
    double i0, i2;
    if (ar < 1e-3) {
      i0 = r - a * r * r / 2.0;
      i2 = r * r * r / 3.0 - a * r * r * r * r / 4.0;
    } else {
      const double e = std::exp(-ar);
      i0 = (1.0 - e) / a;
      i2 = (2.0 - e * (ar * ar + 2.0 * ar + 2.0)) / (a * a * a);
    }
    c[i] = static_cast<float>(medium.sigmaS[i] * density * (i0 - b * i2));
  }
  return c;
}

std::vector<std::string> MediaPass::gridSummary() const {
  std::vector<std::string> out;
  for (int g = 0; g < grids_.count(); ++g) out.push_back(gridMediumNames_[g] + ": " + grids_.summary(g));
  return out;
}

void MediaPass::upload(const Scene& scene, float clampBound, bool gridInBuffer) {
  // Media that neither absorb nor scatter change nothing (mediumIntervals leaves them out too); beyond the limits
  // (mediaFitProblem refuses such a scene) a medium is left out, a grid drawn as a uniform box.
  std::vector<const Medium*> drawn;
  for (const Medium& m : scene.media)
    if (!m.isVacuum() && static_cast<int>(drawn.size()) < kPreviewMaxMedia) drawn.push_back(&m);
  layout_ = {};
  layout_.count = static_cast<int>(drawn.size());
  std::vector<DensityGridsGpu::Wanted> wanted;
  gridMediumNames_.clear();
  const int maxTextureSide = max3dTextureSize();
  for (int i = 0; i < layout_.count; ++i) {
    const Medium& m = *drawn[i];
    if (!m.heterogeneous() || static_cast<int>(wanted.size()) == kPreviewMaxDensityGrids) continue;
    const DensityGridStorage storage = densityGridStorage(*m.density, maxTextureSide, gridInBuffer);
    if (storage == DensityGridStorage::Buffer) layout_.gridsInBuffer |= 1u << wanted.size();
    wanted.push_back({m.density, storage});
    layout_.gridMedia.push_back(i);
    gridMediumNames_.push_back(m.name);
  }
  grids_.update(wanted);

  MediaTableGpu gpu{};
  for (int i = 0; i < layout_.count; ++i) {
    const Medium& m = *drawn[i];
    float density = 1.0f;
    if (const int g = layout_.gridOf(i); g >= 0) {
      gpu.grids[g] = gridRow(m, grids_.storage(g), grids_.bufferOffset(g));
      density = m.densityScale * grids_.weightedDensity(g);
    }
    gpu.media[i] = {glm::vec4(m.sigmaT(), m.fillsSpace ? 1.0f : 0.0f), glm::vec4(m.sigmaS, m.g), m.boxFromWorld,
                    glm::vec4(approximateCompensationFactor(m, clampBound, density), 0.0f)};
  }
  table_.assign(&gpu, sizeof(gpu));
  uploadedBound_ = clampBound;
  if (layout_.count > 0 && layout_ != composeMedia_) {
    compose_ = std::make_unique<ShaderProgram>(
        std::vector<std::string>{"preview/fullscreen.vert.glsl", "preview/media_compose.frag.glsl"}, layout_.defines());
    composeMedia_ = layout_;
  }
}

void MediaPass::bind() const {
  table_.bindUniform(binding(BufferBinding::Media));
  grids_.bind();
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

bool MediaPass::draw(const Frame& frame, const Settings& settings, const InterleavedLayout& layout,
                     const DirectLightPass& direct, const VplGatherPass& gather, const VplVisibility& visibility,
                     const GlVertexArray& vao, bool lights, bool vpls, const std::function<bool()>& outOfTime) {
  ensureTargets(layout);
  slices_.begin(outOfTime);
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
  if (lights) {
    const DirectLightPass::TableView table = direct.bindTable();
    if (!lights_ || lightsLayoutCapacity_ != table.layout.capacity || lightsMedia_ != layout_) {
      std::vector<std::string> defines = layout_.defines();
      defines.push_back(uniformTableDefine("DIRECT_UBO_LIGHTS", table.layout));
      lights_ = std::make_unique<ShaderProgram>(
          std::vector<std::string>{"preview/fullscreen.vert.glsl", "preview/media_lights.frag.glsl"}, defines);
      lightsLayoutCapacity_ = table.layout.capacity;
      lightsMedia_ = layout_;
    }
    ShaderProgram& program = *lights_;
    common(program);
    program.set("uMediaSteps", kMediaLightSteps);
    program.set("uAreaSteps", areaLightSteps(table.areaEnd, k2));
    program.set("uLightShadowTexel", 2.0f / static_cast<float>(table.sizes.punctualFace));
    program.set("uAreaShadowTexel", 2.0f / static_cast<float>(table.sizes.areaFace));
    program.set("uSceneCentre", frame.sceneCentre);
    program.set("uSceneRadius", frame.sceneRadius);
    program.set("uDirectionalShadowTexel", 2.0f * frame.sceneRadius / static_cast<float>(table.sizes.directional));
    program.set("uPunctualEnd", table.punctualEnd);
    lightsRaw_->framebuffer.bind(rawWidth_, rawHeight_);
    slices_.step([&] { lightsRaw_->framebuffer.clearColor(0, glm::vec4(0.0f)); });
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    const int step =
        std::max(table.layout.alignment, table.layout.capacity / table.layout.alignment * table.layout.alignment);
    for (int base = 0; base < table.count; base += step) {
      const int end = std::min(table.count, base + step);
      for (int subset = 0; subset < k2; ++subset) {
        const int sx = subset % k, sy = subset / k;
        const glm::ivec2 origin(sx * layout.blockWidth, sy * layout.blockHeight);
        slices_.bands(glm::ivec4(origin, layout.blockWidth, layout.blockHeight), [&] {
          table.buffer->bindUniformRange(binding(BufferBinding::DirectLights),
                                         static_cast<std::size_t>(base) * table.layout.elementBytes,
                                         static_cast<std::size_t>(end - base) * table.layout.elementBytes);
          program.set("uUboBase", base);
          program.set("uLightBegin", base);
          program.set("uLightEnd", end);
          program.set("uAreaEnd", std::min(end, table.areaEnd));
          glViewport(origin.x, origin.y, layout.blockWidth, layout.blockHeight);
          program.set("uSubsetXY", glm::ivec2(sx, sy));
          program.set("uBlockOrigin", origin);
          // The first area sample of this subset (index = subset mod k^2) from `base` on.
          program.set("uAreaFirst", base + ((subset - base % k2) % k2 + k2) % k2);
          drawFullscreen(program, vao);
        });
      }
    }
    glDisable(GL_BLEND);
  }

  // The VPLs' in-scattering, with the gather's table and maps.
  if (vpls) {
    ShaderProgram& program = (*vpls_)[frame.lambertOnly];
    common(program);
    program.set("uClampBound", settings.clampBound);
    program.set("uShadowFar", frame.far);
    program.set("uShadowBias", frame.bias);
    gather.drawTable(program, visibility, *vplsRaw_, layout, vao, slices_);
  }

  // The merge of the k x k subsets, both results at once: after every band of both, whose neighbours it reads.
  merged_->framebuffer.bind(layout.width, layout.height);
  lightsRaw_->texture.bind(unit(TextureUnit::PassInput0));
  vplsRaw_->texture.bind(unit(TextureUnit::PassInput1));
  merge_->set("uInterleave", k);
  merge_->set("uBlockSize", glm::ivec2(layout.blockWidth, layout.blockHeight));
  merge_->set("uImageSize", glm::ivec2(layout.width, layout.height));
  merge_->set("uCameraPosition", frame.camera.position);
  slices_.bands(glm::ivec4(0, 0, layout.width, layout.height), [&] { drawFullscreen(merge_.get(), vao); });
  return slices_.end();
}

void MediaPass::compose(const Frame& frame, const GlTexture& surface, glm::vec4 weights, int width, int height,
                        GlFramebuffer& out, const GlVertexArray& vao, PassSlices& slices) {
  if (!surfaceCopy_ || surfaceCopy_->texture.width() != width || surfaceCopy_->texture.height() != height)
    surfaceCopy_ = std::make_unique<Target>(width, height);
  slices.step([&] { surfaceCopy_->texture.copyFrom(surface); });
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
  slices.bands(glm::ivec4(0, 0, width, height), [&] { drawFullscreen(compose, vao); });
}

}  // namespace vplab
