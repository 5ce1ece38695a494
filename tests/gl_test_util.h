#pragma once
// A test fixture that runs every test of a suite once on OSMesa and once on EGL, each with its own headless context
// (a context that cannot be made is a failure, not a skip).

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "renderer/gl/context.h"

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

}  // namespace vplab::test

/// Instantiates a GlBackendTest suite for OSMesa and EGL.
#define VPLAB_GL_BACKENDS(Suite) \
  INSTANTIATE_TEST_SUITE_P(Backends, Suite, ::testing::Values(GlBackend::OsMesa, GlBackend::Egl), test::glBackendName)
