#include "renderer/gl/shadow_maps.h"

#include <glad/gl.h>

#include <algorithm>
#include <glm/gtc/matrix_transform.hpp>
#include <stdexcept>

#include "renderer/gl/gl_scene.h"
#include "renderer/gl/texture_units.h"

namespace vplab {

int CubeShadowMaps::render(const GlScene& scene, const std::vector<glm::vec3>& casters, int faceSize, float far,
                           int first, const std::function<bool()>& outOfTime) {
  if (!program_.valid())
    program_ = ShaderProgram({"preview/shadow.vert.glsl", "preview/shadow.geom.glsl", "preview/shadow.frag.glsl"});
  GLint maxLayers = 0;
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
  capacity_ = std::max(1, static_cast<int>(maxLayers) / 6);
  count_ = static_cast<int>(casters.size());
  far_ = far;
  int chunks = (count_ + capacity_ - 1) / capacity_;
  // Keep the textures while they hold the casters: a new VPL set has about as many VPLs as the last (225-281 for 256
  // expected on the smoke box), and a fresh array costs its size in page faults, as llvmpipe zero-fills it (for 281
  // VPLs at 128^2, 55 MB: about 100 ms on a 2-core VM, docs/benchmarks.md "Smoke in the preview"). An array that
  // grows gets a quarter more than it needs; one that would hold over twice the casters is made anew.
  bool reuse = faceSize == faceSize_ && static_cast<int>(chunks_.size()) == chunks;
  for (int c = 0; reuse && c < chunks; ++c) {
    const int layers = chunks_[static_cast<std::size_t>(c)].layers(), needed = 6 * (chunkEnd(c) - chunkBegin(c));
    reuse = layers >= needed && layers <= 2 * needed;
  }
  if (!reuse) {
    const bool growing = faceSize == faceSize_ && !chunks_.empty();
    chunks_.clear();
    for (int c = 0; c < chunks; ++c) {
      const int casters = chunkEnd(c) - chunkBegin(c);
      const int allocated = growing ? std::min(capacity_, casters + (casters + 3) / 4) : casters;
      // A plain 2D array of 6 faces per caster, not a cube-map array: the lookup selects the face itself
      // (shadow.glsl), because llvmpipe's seamless cube filtering costs several times a 2D-array PCF fetch.
      // 16-bit depth: the stored distance / far (far = 2 scene diagonals) is quantised to 3e-5 diagonals, far below
      // the depth bias (0.002 diagonals by default), and the gather, which misses the cache on nearly every shadow
      // fetch, reads half the bytes (8% faster at 640x480, 291 VPLs, k = 4).
      chunks_.push_back(GlTexture(faceSize, faceSize, TextureFormat::Depth16, 1, 6 * allocated, true));
      chunks_.back().setDepthCompare(true);
    }
    faceSize_ = faceSize;
  }
  if (count_ == 0) return -1;
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
      if (i + 1 < count_ && outOfTime()) {
        next = i + 1;
        break;
      }
    }
  }
  glDisable(GL_DEPTH_TEST);
  return next;
}

int CubeShadowMaps::renderMoved(const GlScene& scene, const std::vector<glm::vec3>& casters,
                                const std::vector<int>& moved, int first, const std::function<bool()>& outOfTime) {
  if (static_cast<int>(casters.size()) != count_ || !program_.valid())
    throw std::logic_error("CubeShadowMaps::renderMoved: the casters of the last render are not those");
  beginDraws(scene, casters, far_);
  const float cleared = 1.0f;
  int next = -1;
  for (int k = std::max(0, first); k < static_cast<int>(moved.size()); ++k) {
    const int caster = moved[static_cast<std::size_t>(k)];
    const int c = caster / capacity_;
    const GlTexture& chunk = chunks_[static_cast<std::size_t>(c)];
    const int layer = 6 * (caster - chunkBegin(c));
    // Only this caster's six faces are cleared and drawn.
    glClearTexSubImage(chunk.id(), 0, 0, 0, layer, faceSize_, faceSize_, 6, GL_DEPTH_COMPONENT, GL_FLOAT, &cleared);
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
  glDisable(GL_DEPTH_TEST);
  return next;
}

void CubeShadowMaps::beginDraws(const GlScene& scene, const std::vector<glm::vec3>& casters, float far) {
  std::vector<glm::vec4> positions(casters.size());
  for (std::size_t i = 0; i < casters.size(); ++i) positions[i] = glm::vec4(casters[i], 1.0f);
  casterBuffer_.assign(positions.data(), positions.size() * sizeof(glm::vec4));
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
}

}  // namespace vplab
