#include "renderer/gl/shadow_maps.h"

#include <glad/gl.h>

#include <glm/gtc/matrix_transform.hpp>
#include <stdexcept>

#include "renderer/gl/gl_scene.h"
#include "renderer/gl/texture_units.h"

namespace vplab {

namespace {
// A caster as shaders/preview/shadow.geom.glsl reads it.
struct CasterGpu {
  glm::vec4 position;  // w: its first layer in its chunk
  glm::vec4 normal;    // w: 1 for a hemicube, whose frame the lookup builds from the same normal (the VPL table's)
};
}  // namespace

void CubeShadowMaps::layOut(const std::vector<VplCaster>& casters) {
  GLint maxLayers = 0;
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
  maxLayers_ = std::max(6, static_cast<int>(maxLayers));
  wholeCubes_ = 0;
  while (wholeCubes_ < static_cast<int>(casters.size()) && casters[static_cast<std::size_t>(wholeCubes_)].inMedium)
    ++wholeCubes_;
  for (std::size_t i = static_cast<std::size_t>(wholeCubes_); i < casters.size(); ++i)
    if (casters[i].inMedium)
      throw std::logic_error("CubeShadowMaps: medium VPLs must come before surface VPLs (gatherOrder)");
  chunkBegins_.assign(1, 0);
  firstLayers_.resize(casters.size());
  int layer = 0;
  for (int c = 0; c < static_cast<int>(casters.size()); ++c) {
    if (layer + layersOf(c) > maxLayers_) {
      chunkBegins_.push_back(c);
      layer = 0;
    }
    firstLayers_[static_cast<std::size_t>(c)] = layer;
    layer += layersOf(c);
  }
  if (!casters.empty()) chunkBegins_.push_back(static_cast<int>(casters.size()));
}

int CubeShadowMaps::render(const GlScene& scene, const std::vector<VplCaster>& casters, int faceSize, float far,
                           int first, const std::function<bool()>& outOfTime) {
  if (!program_.valid())
    program_ = ShaderProgram({"preview/shadow.vert.glsl", "preview/shadow.geom.glsl", "preview/shadow.frag.glsl"});
  // The layers each chunk needs now, against what its texture holds.
  std::vector<int> held;
  for (const GlTexture& t : chunks_) held.push_back(t.layers());
  layOut(casters);
  far_ = far;
  const int chunks = static_cast<int>(chunkBegins_.size()) - 1;
  auto layersNeeded = [&](int c) { return firstLayers_[chunkEnd(c) - 1] + layersOf(chunkEnd(c) - 1); };
  // Keep the textures while they hold the maps: a new VPL set has about as many VPLs as the last (225-281 for 256
  // expected on the smoke box), and a fresh array costs its size in page faults, as llvmpipe zero-fills it (for 281
  // whole cubes at 128^2, 55 MB: about 100 ms on a 2-core VM, docs/benchmarks.md "Smoke in the preview"). An array
  // that grows gets a quarter more than it needs; one that would hold over twice the layers is made anew.
  bool reuse = faceSize == faceSize_ && static_cast<int>(held.size()) == chunks;
  for (int c = 0; reuse && c < chunks; ++c) {
    const int needed = layersNeeded(c);
    reuse = held[static_cast<std::size_t>(c)] >= needed && held[static_cast<std::size_t>(c)] <= 2 * needed;
  }
  if (!reuse) {
    const bool growing = faceSize == faceSize_ && !chunks_.empty();
    chunks_.clear();
    for (int c = 0; c < chunks; ++c) {
      const int needed = layersNeeded(c);
      const int allocated = growing ? std::min(maxLayers_, needed + (needed + 3) / 4) : needed;
      // 16-bit depth: the stored distance / far (far = 2 scene diagonals) is quantised to 3e-5 diagonals, far below
      // the depth bias (0.002 diagonals by default), and the gather, which misses the cache on nearly every shadow
      // fetch, reads half the bytes (8% faster at 640x480, 291 VPLs, k = 4).
      chunks_.push_back(GlTexture(faceSize, faceSize, TextureFormat::Depth16, 1, allocated, true));
      chunks_.back().setDepthCompare(true);
    }
    faceSize_ = faceSize;
  }
  if (casters.empty()) return -1;
  beginDraws(scene, casters, far);
  int next = -1;
  for (int c = 0; c < chunkCount() && next < 0; ++c) {
    if (chunkEnd(c) <= first) continue;
    framebuffer_.attachDepth(chunks_[static_cast<std::size_t>(c)]);
    framebuffer_.finalize(0);
    framebuffer_.bind(faceSize, faceSize);
    // A chunk is cleared once, when its first caster is drawn; a resumed update goes on drawing into it.
    if (first <= chunkBegin(c)) framebuffer_.clearDepth(1.0f);
    program_.set("uFirstCaster", chunkBegin(c));
    if (!outOfTime) {
      program_.set("uInstanceOffset", 0);
      drawProceduralTriangles(3 * scene.triangleCount(), chunkEnd(c) - chunkBegin(c));
      continue;
    }
    for (int i = std::max(first, chunkBegin(c)); i < chunkEnd(c); ++i) {
      program_.set("uInstanceOffset", i - chunkBegin(c));
      drawProceduralTriangles(3 * scene.triangleCount(), 1);
      if (i + 1 < casterCount() && outOfTime()) {
        next = i + 1;
        break;
      }
    }
  }
  endDraws();
  return next;
}

int CubeShadowMaps::renderMoved(const GlScene& scene, const std::vector<VplCaster>& casters,
                                const std::vector<int>& moved, int first, const std::function<bool()>& outOfTime) {
  if (static_cast<int>(casters.size()) != casterCount() || !program_.valid())
    throw std::logic_error("CubeShadowMaps::renderMoved: the casters of the last render are not those");
  for (int c = 0; c < casterCount(); ++c)
    if (casters[static_cast<std::size_t>(c)].inMedium != (c < wholeCubes_))
      throw std::logic_error("CubeShadowMaps::renderMoved: a caster's map changed between a cube and a hemicube");
  beginDraws(scene, casters, far_);
  const float cleared = 1.0f;
  int next = -1;
  for (int k = std::max(0, first); k < static_cast<int>(moved.size()); ++k) {
    const int caster = moved[static_cast<std::size_t>(k)];
    int c = 0;
    while (caster >= chunkEnd(c)) ++c;
    const GlTexture& chunk = chunks_[static_cast<std::size_t>(c)];
    // Only this caster's layers are cleared and drawn.
    glClearTexSubImage(chunk.id(), 0, 0, 0, firstLayers_[static_cast<std::size_t>(caster)], faceSize_, faceSize_,
                       layersOf(caster), GL_DEPTH_COMPONENT, GL_FLOAT, &cleared);
    framebuffer_.attachDepth(chunk);
    framebuffer_.finalize(0);
    framebuffer_.bind(faceSize_, faceSize_);
    program_.set("uFirstCaster", chunkBegin(c));
    program_.set("uInstanceOffset", caster - chunkBegin(c));
    drawProceduralTriangles(3 * scene.triangleCount(), 1);
    if (outOfTime && k + 1 < static_cast<int>(moved.size()) && outOfTime()) {
      next = k + 1;
      break;
    }
  }
  endDraws();
  return next;
}

void CubeShadowMaps::beginDraws(const GlScene& scene, const std::vector<VplCaster>& casters, float far) {
  std::vector<CasterGpu> gpu(casters.size());
  for (std::size_t i = 0; i < casters.size(); ++i) {
    const bool hemicube = static_cast<int>(i) >= wholeCubes_;
    gpu[i] = {glm::vec4(casters[i].position, static_cast<float>(firstLayers_[i])),
              glm::vec4(hemicube ? casters[i].normal : glm::vec3(0.0f), hemicube ? 1.0f : 0.0f)};
  }
  casterBuffer_.assign(gpu.data(), gpu.size() * sizeof(CasterGpu));
  casterBuffer_.bindStorage(binding(BufferBinding::ShadowCasters));

  // Cube face orientations of the GL specification (table 8.19), as rotations of the offset from the caster;
  // shaders/common/shadow.glsl inverts exactly these.
  static const glm::vec3 kTargets[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  static const glm::vec3 kUps[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
  glm::mat3 rotations[6];
  for (int f = 0; f < 6; ++f) rotations[f] = glm::mat3(glm::lookAt(glm::vec3(0.0f), kTargets[f], kUps[f]));
  glProgramUniformMatrix3fv(program_.id(), program_.location("uFaceRotation"), 6, GL_FALSE, &rotations[0][0][0]);
  program_.set("uProjection", glm::perspective(glm::radians(90.0f), 1.0f, far * 1e-5f, far));
  program_.set("uShadowFar", far);

  scene.bind();
  program_.use();
  vao_.bind();
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  // A hemicube's side faces keep their upper half (shadow.geom.glsl).
  glEnable(GL_CLIP_DISTANCE0);
  glEnable(GL_CLIP_DISTANCE1);
}

void CubeShadowMaps::endDraws() {
  glDisable(GL_CLIP_DISTANCE0);
  glDisable(GL_CLIP_DISTANCE1);
  glDisable(GL_DEPTH_TEST);
}

}  // namespace vplab
