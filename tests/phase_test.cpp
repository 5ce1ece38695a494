// The Henyey-Greenstein phase function (renderer/scene/medium.h, docs/theory.md §16): normalised over the sphere,
// sampled with exactly the density it reports (chi-square over cos t and phi), mean cosine g with the convention
// that g > 0 keeps the light travelling on (wi close to -wo), and reciprocal. The GLSL mirror
// (shaders/common/phase.glsl) is checked against it on a grid of (cos, g) and on sampled directions.

#include "renderer/core/sampling.h"
#include "renderer/gl/context.h"
#include "renderer/gl/resources.h"
#include "renderer/gl/shader.h"
#include "renderer/scene/medium.h"
#include "tests/test_tmp.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace vplab {
namespace {

const float kGs[] = {-0.9f, -0.5f, 0.0f, 0.3f, 0.8f, 0.95f};

/// The formula of docs/theory.md §16 in double, written independently of the code under test.
double hgDouble(double cosT, double g) {
  double denom = 1.0 + g * g - 2.0 * g * cosT;
  return (1.0 - g * g) / (4.0 * M_PI * std::pow(denom, 1.5));
}

/// Composite Simpson over cos t in [a, b] of f(cos t) (n even intervals).
template <class F>
double simpson(F&& f, double a, double b, int n) {
  const double h = (b - a) / n;
  double sum = f(a) + f(b);
  for (int i = 1; i < n; ++i) sum += f(a + i * h) * ((i & 1) ? 4.0 : 2.0);
  return sum * h / 3.0;
}

glm::vec3 unitDir(float cosT, float phi) {
  float s = std::sqrt(std::max(0.0f, 1.0f - cosT * cosT));
  return {s * std::cos(phi), s * std::sin(phi), cosT};
}

TEST(PhaseHG, IntegratesToOneOverTheSphere) {
  for (float g : kGs) {
    // Over cos t (the azimuth gives 2 pi): the float function, summed in double. Fine steps resolve the g = 0.95
    // peak (width about 1 - g around cos t = 1).
    double total = 2.0 * M_PI * simpson([&](double c) { return static_cast<double>(phaseHG(static_cast<float>(c), g)); },
                                        -1.0, 1.0, 200000);
    EXPECT_NEAR(total, 1.0, 1e-5) << "g " << g;
    // The direction form over a (cos, phi) grid around an arbitrary wo: the same integral through phaseHG(wo, wi).
    const glm::vec3 wo = glm::normalize(glm::vec3(0.3f, -0.5f, 0.8f));
    Frame frame(wo);
    const int nc = 20000, np = 16;
    double sum = 0.0;
    for (int i = 0; i < nc; ++i)
      for (int j = 0; j < np; ++j) {
        float c = -1.0f + 2.0f * (static_cast<float>(i) + 0.5f) / nc;
        float phi = 2.0f * kPi * (static_cast<float>(j) + 0.5f) / np;
        glm::vec3 wi = frame.toWorld(unitDir(c, phi));
        sum += phaseHG(wo, wi, g);
      }
    // Midpoint rule: cell solid angle (2 / nc) (2 pi / np); the g = 0.95 peak's curvature limits it to about 2e-4.
    EXPECT_NEAR(sum * (2.0 / nc) * (2.0 * M_PI / np), 1.0, 1e-3) << "g " << g;
  }
}

TEST(PhaseHG, MatchesTheFormulaAndIsotropicAtZero) {
  for (float g : kGs)
    for (int i = 0; i <= 40; ++i) {
      double c = -1.0 + 2.0 * i / 40.0;
      // A few float roundings: the peak is computed without cancellation.
      EXPECT_NEAR(phaseHG(static_cast<float>(c), g), hgDouble(c, g), 2e-6 * hgDouble(c, g)) << g << " " << c;
    }
  EXPECT_NEAR(phaseHG(0.3f, 0.0f), 1.0 / (4.0 * M_PI), 1e-8);
}

TEST(PhaseHG, ForwardScatteringPeaksWhereTheLightKeepsTravelling) {
  // wo toward the viewer, wi toward the light: light that keeps its direction arrives from behind the point as seen
  // from the viewer, wi = -wo. g > 0 must favour it, g < 0 the return toward the light (wi = wo).
  const glm::vec3 wo = glm::normalize(glm::vec3(0.2f, 0.7f, -0.4f));
  EXPECT_GT(phaseHG(wo, -wo, 0.8f), 10.0f * phaseHG(wo, wo, 0.8f));
  EXPECT_LT(phaseHG(wo, -wo, -0.8f), 0.1f * phaseHG(wo, wo, -0.8f));
}

TEST(PhaseHG, MeanCosineIsG) {
  for (float g : kGs) {
    // Quadrature: mean cos t = 2 pi integral cos f dcos.
    double mean = 2.0 * M_PI * simpson([&](double c) { return c * hgDouble(c, g); }, -1.0, 1.0, 200000);
    EXPECT_NEAR(mean, g, 1e-6) << "g " << g;
    // Sampling: cos t = -dot(wi, wo) averages to g.
    const glm::vec3 wo = glm::normalize(glm::vec3(-0.6f, 0.1f, 0.3f));
    Rng rng(hashKey(31, static_cast<uint64_t>(std::lround(g * 100.0f) + 100)));
    const int n = 400000;
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; ++i) {
      PhaseSample s = samplePhaseHG(wo, g, rng.next2D());
      double c = -glm::dot(s.wi, wo);
      sum += c;
      sum2 += c * c;
    }
    double m = sum / n, sd = std::sqrt(std::max(0.0, sum2 / n - m * m) / n);
    EXPECT_NEAR(m, g, 5.0 * sd + 1e-5) << "g " << g << " sample mean " << m << " +- " << sd;
  }
}

TEST(PhaseHG, IsReciprocal) {
  Rng rng(5);
  for (float g : kGs)
    for (int i = 0; i < 200; ++i) {
      glm::vec3 a = unitDir(2.0f * rng.next1D() - 1.0f, 2.0f * kPi * rng.next1D());
      glm::vec3 b = unitDir(2.0f * rng.next1D() - 1.0f, 2.0f * kPi * rng.next1D());
      float ab = phaseHG(a, b, g), ba = phaseHG(b, a, g);
      EXPECT_NEAR(ab, ba, 1e-6f * std::max(ab, ba)) << g;
    }
}

/// Chi-square statistic of samplePhaseHG() against its own pdf over a grid of nc bins in cos t (uniform in the
/// HG cdf of the exact density, so every bin expects the same count) times np bins in phi around wo; writes the
/// degrees of freedom. Also checks each sample's reported pdf and unit length.
double chiSquare(float g, int n, int nc, int np, int& dof) {
  const glm::vec3 wo = glm::normalize(glm::vec3(0.5f, 0.5f, -0.7f));
  Frame frame(wo);
  // Bin edges in cos t from the exact cdf, by bisection on the double formula's closed-form cdf.
  auto cdf = [&](double c) {
    if (std::abs(g) < 1e-6) return 0.5 * (c + 1.0);
    double gg = g;
    return (1.0 - gg * gg) / (2.0 * gg) * (1.0 / std::sqrt(1.0 + gg * gg - 2.0 * gg * c) - 1.0 / (1.0 + gg));
  };
  std::vector<double> edges(nc + 1);
  edges[0] = -1.0;
  edges[nc] = 1.0;
  for (int k = 1; k < nc; ++k) {
    double lo = -1.0, hi = 1.0, target = static_cast<double>(k) / nc;
    for (int it = 0; it < 80; ++it) {
      double mid = 0.5 * (lo + hi);
      (cdf(mid) < target ? lo : hi) = mid;
    }
    edges[k] = 0.5 * (lo + hi);
  }
  std::vector<double> counts(static_cast<std::size_t>(nc) * np, 0.0);
  Rng rng(hashKey(77, static_cast<uint64_t>(std::lround(g * 100.0f) + 100)));
  int badPdf = 0, badLength = 0;
  for (int i = 0; i < n; ++i) {
    PhaseSample s = samplePhaseHG(wo, g, rng.next2D());
    if (std::abs(glm::length(s.wi) - 1.0f) > 1e-4f) ++badLength;
    float expectPdf = phaseHG(wo, s.wi, g);
    if (std::abs(s.pdf - expectPdf) > 1e-3f * expectPdf + 1e-6f) ++badPdf;
    // The direction light travelled before scattering, in wo's frame: cos t = dot(dIn, wo).
    glm::vec3 local = frame.toLocal(-s.wi);
    double c = std::clamp(static_cast<double>(local.z), -1.0, 1.0);
    double phi = std::atan2(static_cast<double>(local.y), static_cast<double>(local.x));
    if (phi < 0.0) phi += 2.0 * M_PI;
    int ic = static_cast<int>(std::upper_bound(edges.begin(), edges.end(), c) - edges.begin()) - 1;
    ic = std::clamp(ic, 0, nc - 1);
    int ip = std::clamp(static_cast<int>(phi / (2.0 * M_PI) * np), 0, np - 1);
    counts[static_cast<std::size_t>(ic) * np + ip] += 1.0;
  }
  EXPECT_EQ(badPdf, 0) << "g " << g;
  EXPECT_EQ(badLength, 0) << "g " << g;
  const double expected = static_cast<double>(n) / (nc * np);
  double chi2 = 0.0;
  for (double c : counts) chi2 += (c - expected) * (c - expected) / expected;
  dof = nc * np - 1;
  return chi2;
}

TEST(PhaseHG, SamplingDrawsItsPdf) {
  for (float g : kGs) {
    int dof = 0;
    // 64 x 16 bins, about 490 samples per bin: the chi-square statistic has mean dof and sd sqrt(2 dof) = 45.
    double chi2 = chiSquare(g, 500000, 64, 16, dof);
    EXPECT_LT(chi2, dof + 6.0 * std::sqrt(2.0 * dof)) << "g " << g << " chi2 " << chi2 << " dof " << dof;
  }
}

// --- the GLSL mirror ---------------------------------------------------------------------------------------------

/// Copies shaders/common/{phase,math}.glsl and a fragment shader evaluating them into a directory of the test's own,
/// so that the real include file is compiled by the project's loader.
std::string writePhaseShaders() {
  namespace fs = std::filesystem;
  fs::path dir = fs::path(test::tmpDir()) / "gl_phase";
  fs::create_directories(dir / "common");
  for (const char* f : {"common/phase.glsl", "common/math.glsl"})
    fs::copy_file(fs::path(defaultShaderDir()) / f, dir / f, fs::copy_options::overwrite_existing);
  std::ofstream(dir / "quad.vert.glsl") << "#version 450 core\n"
                                           "void main() {\n"
                                           "  vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);\n"
                                           "  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);\n"
                                           "}\n";
  // Pixel (x, y) of 65 x 8: cos t = -1 + x / 32, g = uG[y]; r: phaseHG(cos, g); g: the direction form through wo
  // and a wi with that cosine; b, a: -dot(wi, wo) and wi.x of samplePhaseHG(wo, g, u), u = (x / 64, 0.37).
  std::ofstream(dir / "phase.frag.glsl")
      << "#version 450 core\n"
         "#include \"common/phase.glsl\"\n"
         "uniform float uG[8];\n"

         "uniform vec3 uWo;\n"
         "layout(location = 0) out vec4 outColor;\n"
         "void main() {\n"
         "  int x = int(gl_FragCoord.x), y = int(gl_FragCoord.y);\n"
         "  float c = -1.0 + float(x) * 0.03125;\n"
         "  float g = uG[y];\n"
         "  vec3 s, t;\n"
         "  orthonormalFrame(uWo, s, t);\n"
         "  vec3 wi = -(s * sqrt(max(0.0, 1.0 - c * c)) + uWo * c);\n"
         "  vec3 ws = samplePhaseHG(uWo, g, vec2(float(x) * 0.015625, 0.37));\n"
         "  outColor = vec4(phaseHG(c, g), phaseHG(uWo, wi, g), -dot(ws, uWo), ws.x);\n"
         "}\n";
  return dir.string();
}

class GlPhase : public ::testing::TestWithParam<GlBackend> {};

TEST_P(GlPhase, GlslMirrorsTheCpp) {
  HeadlessGlContext context(GetParam());
  const std::string dir = writePhaseShaders();
  ShaderProgram program({"quad.vert.glsl", "phase.frag.glsl"}, {}, dir);
  constexpr int kW = 65, kH = 8;
  const float gs[kH] = {-0.9f, -0.5f, 0.0f, 0.0005f, 0.3f, 0.8f, 0.95f, 0.99f};
  const glm::vec3 wo = glm::normalize(glm::vec3(0.3f, -0.4f, 0.8f));
  GlTexture color(kW, kH, TextureFormat::Rgba32F);
  GlFramebuffer fb;
  fb.attachColor(0, color);
  fb.finalize(1);
  fb.bind(kW, kH);
  program.set("uWo", wo);
  for (int y = 0; y < kH; ++y) program.set(("uG[" + std::to_string(y) + "]").c_str(), gs[y]);
  program.use();
  GlVertexArray vao;
  vao.bind();
  drawProceduralTriangles(3);
  std::vector<glm::vec4> px = readFramebufferRgba(fb, 0, kW, kH);
  checkGlError("phase test");
  ASSERT_EQ(px.size(), static_cast<std::size_t>(kW * kH));
  Frame frame(wo);
  double worst = 0.0, worstSample = 0.0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      // readFramebufferRgba puts row 0 at the top: GL row y is image row kH - 1 - y.
      const glm::vec4 v = px[static_cast<std::size_t>(kH - 1 - y) * kW + x];
      const float g = gs[y];
      // Exact in binary on both sides: no division whose rounding could differ between the compilers.
      const float c = -1.0f + static_cast<float>(x) * 0.03125f;
      const float expect = phaseHG(c, g);
      const glm::vec3 wi = -(frame.s * std::sqrt(std::max(0.0f, 1.0f - c * c)) + wo * c);
      const float expectDir = phaseHG(wo, wi, g);
      PhaseSample s = samplePhaseHG(wo, g, {static_cast<float>(x) * 0.015625f, 0.37f});
      worst = std::max({worst, static_cast<double>(std::abs(v.r - expect) / expect),
                        static_cast<double>(std::abs(v.g - expectDir) / expectDir)});
      worstSample = std::max({worstSample, static_cast<double>(std::abs(v.b + glm::dot(s.wi, wo))),
                              static_cast<double>(std::abs(v.a - s.wi.x))});
      EXPECT_NEAR(v.r, expect, 1e-4f * expect) << "x " << x << " g " << g;
      // The direction form passes cos t through a dot product: near the g = 0.99 peak a rounding of 1e-7 in it moves
      // f_p by 3e-3.
      EXPECT_NEAR(v.g, expectDir, 1e-2f * expectDir) << "x " << x << " g " << g;
      // The sample's cosine is exact up to float rounding; near cos t = +-1 the azimuth is ill-conditioned, so
      // compare one coordinate of wi loosely.
      EXPECT_NEAR(v.b, -glm::dot(s.wi, wo), 2e-3f) << "x " << x << " g " << g;
      EXPECT_NEAR(v.a, s.wi.x, 5e-3f) << "x " << x << " g " << g;
    }
  std::printf("GLSL vs C++ phaseHG: worst relative difference %.3g, sampled direction %.3g (%s)\n", worst,
              worstSample, context.description().c_str());
}

INSTANTIATE_TEST_SUITE_P(Backends, GlPhase, ::testing::Values(GlBackend::OsMesa, GlBackend::Egl),
                         [](const auto& info) { return std::string(info.param == GlBackend::Egl ? "Egl" : "OsMesa"); });

}  // namespace
}  // namespace vplab
