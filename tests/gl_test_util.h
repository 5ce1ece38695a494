#pragma once
// A test fixture that runs every test of a suite once on OSMesa and once on EGL, each with its own headless context
// (a context that cannot be made is a failure, not a skip).

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <memory>
#include <string>

#include "renderer/gl/context.h"
#include "renderer/image/image.h"
#include "renderer/settings.h"

namespace vplab::test {

class GlBackendTest : public ::testing::TestWithParam<GlBackend> {
 protected:
  void SetUp() override { context_ = std::make_unique<HeadlessGlContext>(GetParam()); }
  void TearDown() override { context_.reset(); }
  std::unique_ptr<HeadlessGlContext> context_;
};

inline std::string glBackendName(const ::testing::TestParamInfo<GlBackend>& info) {
  return info.param == GlBackend::Egl ? "Egl" : "OsMesa";
}

/// Settings of the tests that compare the preview's indirect light with the CPU's VPL render: size x size pixels, the
/// VPL count, two CPU threads, the indirect component, 16 shadow-mapped light samples (the direct light is not compared).
inline Settings indirectSettings(int size, int vpls) {
  Settings s;
  s.width = size;
  s.height = size;
  s.vplCount = vpls;
  s.threads = 2;
  s.components = Components::Indirect;
  s.directLightSamples = 16;
  return s;
}

/// Pixels whose values differ between two images (every pixel when the sizes differ): determinism tests expect 0.
inline std::size_t differingPixels(const Image& a, const Image& b) {
  if (a.pixels.size() != b.pixels.size()) return std::max(a.pixels.size(), b.pixels.size());
  std::size_t differing = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) differing += a.pixels[i] != b.pixels[i];
  return differing;
}

}  // namespace vplab::test

/// Instantiates a GlBackendTest suite for OSMesa and EGL.
#define VPLAB_GL_BACKENDS(Suite) \
  INSTANTIATE_TEST_SUITE_P(Backends, Suite, ::testing::Values(GlBackend::OsMesa, GlBackend::Egl), test::glBackendName)
