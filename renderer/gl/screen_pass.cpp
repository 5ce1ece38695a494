#include "renderer/gl/screen_pass.h"

namespace vplab {

Target::Target(int w, int h, int levels) : texture(w, h, TextureFormat::Rgba32F, levels) {
  framebuffer.attachColor(0, texture);
  framebuffer.finalize(1);
}

void drawFullscreen(ShaderProgram& program, const GlVertexArray& vao) {
  program.use();
  vao.bind();
  drawProceduralTriangles(3);
}

namespace {
std::vector<std::string> withDefine(std::vector<std::string> defines, std::string define) {
  defines.push_back(std::move(define));
  return defines;
}
}  // namespace

BrdfVariants::BrdfVariants(const std::string& fragmentShader, const std::vector<std::string>& defines)
    : general({"preview/fullscreen.vert.glsl", fragmentShader}, defines),
      lambertOnly({"preview/fullscreen.vert.glsl", fragmentShader}, withDefine(defines, "BRDF_LAMBERT_ONLY 1")) {}

}  // namespace vplab
