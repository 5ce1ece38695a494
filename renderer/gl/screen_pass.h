#pragma once
// What the preview's screen passes share: a colour target with its framebuffer, the full-screen triangle, a pass
// compiled for any material and for Lambert-only scenes, and the block layout of interleaved sampling.

#include <string>
#include <vector>

#include "renderer/gl/resources.h"
#include "renderer/gl/shader.h"

namespace vplab {

/// A colour texture with its own framebuffer.
struct Target {
  GlTexture texture;
  GlFramebuffer framebuffer;
  Target(int w, int h, int levels = 1);
};

/// Draws the full-screen triangle (preview/fullscreen.vert.glsl makes it from gl_VertexID) with `program`.
void drawFullscreen(ShaderProgram& program, const GlVertexArray& vao);

/// A screen pass compiled twice: for any material, and with BRDF_LAMBERT_ONLY (common/brdf.glsl) for scenes whose
/// materials are all Lambert, where llvmpipe would otherwise run the GGX code under a lane mask.
struct BrdfVariants {
  ShaderProgram general, lambertOnly;
  BrdfVariants(const std::string& fragmentShader, const std::vector<std::string>& defines = {});
  ShaderProgram& operator[](bool lambert) { return lambert ? lambertOnly : general; }
};

/// Interleaved sampling (common/interleaved.glsl): the width x height image is drawn as k x k blocks of
/// blockWidth x blockHeight texels, block (sx, sy) holding the pixels of subset sx + k sy.
struct InterleavedLayout {
  int width = 0, height = 0, k = 1, blockWidth = 0, blockHeight = 0;
};

}  // namespace vplab
