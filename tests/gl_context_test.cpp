// Headless GL foundation: both backends give a 4.5 core context, FBO clears and a shaded triangle read back
// correctly (row 0 at the top), and shader errors name the file and line. A missing context is a failure, not a
// skip: CI has Mesa llvmpipe.

#include "renderer/gl/context.h"
#include "renderer/gl/resources.h"
#include "renderer/gl/shader.h"
#include "tests/test_tmp.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace vplab {
namespace {

class GlContextTest : public ::testing::TestWithParam<GlBackend> {};

TEST_P(GlContextTest, Creates45CoreContext) {
  HeadlessGlContext context(GetParam());
  EXPECT_EQ(context.backend(), GetParam());
  EXPECT_TRUE(context.majorVersion() > 4 || (context.majorVersion() == 4 && context.minorVersion() >= 5))
      << context.description();
  EXPECT_FALSE(context.renderer().empty());
}

TEST_P(GlContextTest, ClearsAndDrawsTriangle) {
  HeadlessGlContext context(GetParam());
  constexpr int kW = 32, kH = 16;
  GlTexture color(kW, kH, TextureFormat::Rgba32F);
  GlFramebuffer fb;
  fb.attachColor(0, color);
  fb.finalize(1);
  fb.bind(kW, kH);
  // A value outside [0, 1] checks that the float target is not clamped.
  fb.clearColor(0, glm::vec4(0.25f, 2.5f, -1.0f, 1.0f));

  ShaderProgram program({"test/triangle.vert.glsl", "test/triangle.frag.glsl"});
  // Covers the upper-left half of the viewport: NDC (-1,-1), (-1,1), (1,1) is the triangle above the diagonal.
  glm::vec2 corners[3] = {{-1.0f, -1.0f}, {1.0f, 1.0f}, {-1.0f, 1.0f}};
  program.setArray("uCorners", corners, 3);
  program.set("uColor", glm::vec3(0.5f, 0.75f, 3.0f));
  program.use();
  GlVertexArray vao;
  vao.bind();
  drawProceduralTriangles(3);
  Image image = readFramebuffer(fb, 0, kW, kH);
  checkGlError("triangle test");

  ASSERT_EQ(image.width, kW);
  ASSERT_EQ(image.height, kH);
  // Row 0 is the top: the top-left corner is inside the triangle, the bottom-right corner is the clear colour.
  glm::vec3 inside = image.at(1, 1), outside = image.at(kW - 2, kH - 2);
  EXPECT_NEAR(inside.r, 0.5f, 1e-5f);
  EXPECT_NEAR(inside.g, 0.75f, 1e-5f);
  EXPECT_NEAR(inside.b, 3.0f, 1e-5f);
  EXPECT_NEAR(outside.r, 0.25f, 1e-6f);
  EXPECT_NEAR(outside.g, 2.5f, 1e-6f);
  EXPECT_NEAR(outside.b, -1.0f, 1e-6f);
  // Near the top-right corner but above the diagonal: inside; the mirrored point below it: outside.
  EXPECT_NEAR(image.at(kW - 4, 1).b, 3.0f, 1e-5f);
  EXPECT_NEAR(image.at(3, kH - 2).b, -1.0f, 1e-6f);
}

TEST_P(GlContextTest, CompileErrorNamesFileAndLine) {
  HeadlessGlContext context(GetParam(), [](GlMessageSeverity, const std::string&) {});
  try {
    ShaderProgram program({"test/triangle.vert.glsl", "test/broken.frag.glsl"});
    FAIL() << "a broken shader compiled";
  } catch (const ShaderError& e) {
    std::string what = e.what();
    EXPECT_EQ(e.file, "test/broken.frag.glsl") << what;
    EXPECT_EQ(e.line, 7) << what;
    EXPECT_NE(what.find("test/broken.frag.glsl:7"), std::string::npos) << what;
  }
}

INSTANTIATE_TEST_SUITE_P(Gl, GlContextTest, ::testing::Values(GlBackend::OsMesa, GlBackend::Egl),
                         [](const auto& info) { return std::string(toString(info.param)); });

TEST(GlShader, ErrorInIncludedFileNamesThatFile) {
  HeadlessGlContext context(GlBackend::Auto, [](GlMessageSeverity, const std::string&) {});
  std::filesystem::path dir = std::filesystem::path(vplab::test::tmpDir()) / "gl_shader_include";
  std::filesystem::create_directories(dir / "common");
  std::ofstream(dir / "common" / "bad.glsl") << "// line 1\nfloat f() { return missing; }\n";
  std::ofstream(dir / "p.frag.glsl") << "#version 450 core\n#include \"common/bad.glsl\"\nout vec4 c;\n"
                                        "void main() { c = vec4(f()); }\n";
  try {
    ShaderProgram program({"p.frag.glsl"}, {}, dir.string());
    FAIL() << "a broken include compiled";
  } catch (const ShaderError& e) {
    EXPECT_EQ(e.file, "common/bad.glsl") << e.what();
    EXPECT_EQ(e.line, 2) << e.what();
  }
}

TEST(GlShader, MissingIncludeThrowsWithIncluder) {
  HeadlessGlContext context(GlBackend::Auto);
  std::filesystem::path dir = std::filesystem::path(vplab::test::tmpDir()) / "gl_shader_missing";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "m.frag.glsl") << "#version 450 core\n\n#include \"common/none.glsl\"\nvoid main() {}\n";
  try {
    ShaderProgram program({"m.frag.glsl"}, {}, dir.string());
    FAIL() << "a missing include was accepted";
  } catch (const ShaderError& e) {
    EXPECT_NE(std::string(e.what()).find("m.frag.glsl:3"), std::string::npos) << e.what();
  }
}

TEST(GlShader, ReloadKeepsLastWorkingProgram) {
  HeadlessGlContext context(GlBackend::Auto, [](GlMessageSeverity, const std::string&) {});
  std::filesystem::path dir = std::filesystem::path(vplab::test::tmpDir()) / "gl_shader_reload";
  std::filesystem::create_directories(dir);
  auto write = [&](const char* body) { std::ofstream(dir / "r.frag.glsl") << body; };
  write("#version 450 core\nout vec4 c;\nvoid main() { c = vec4(1.0); }\n");
  ShaderProgram program({"r.frag.glsl"}, {}, dir.string());
  uint32_t before = program.id();
  ASSERT_NE(before, 0u);
  write("#version 450 core\nout vec4 c;\nvoid main() { c = oops; }\n");
  std::string error;
  EXPECT_FALSE(program.reload(&error));
  EXPECT_EQ(program.id(), before);
  EXPECT_NE(error.find("r.frag.glsl:3"), std::string::npos) << error;
  write("#version 450 core\nout vec4 c;\nvoid main() { c = vec4(0.5); }\n");
  EXPECT_TRUE(program.reload(&error)) << error;
  EXPECT_TRUE(program.valid());
}

TEST(GlBackendNames, ParseRoundTrip) {
  GlBackend b;
  for (GlBackend x : {GlBackend::Auto, GlBackend::Egl, GlBackend::OsMesa}) {
    ASSERT_TRUE(parseGlBackend(toString(x), b));
    EXPECT_EQ(b, x);
  }
  EXPECT_FALSE(parseGlBackend("glx", b));
}

}  // namespace
}  // namespace vplab
