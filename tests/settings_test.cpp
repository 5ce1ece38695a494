#include "renderer/settings.h"

#include <gtest/gtest.h>

#include <cmath>

namespace vplab {

TEST(Settings, DefaultsAreValid) { EXPECT_TRUE(validateSettings(Settings{}).empty()); }

TEST(Settings, EveryOutOfRangeFieldIsNamed) {
  Settings s;
  s.width = 0;
  s.clampBound = -1.0f;
  s.rejectionEpsilon = std::nanf("");
  s.interleave = 9;
  std::vector<std::string> problems = validateSettings(s);
  ASSERT_EQ(problems.size(), 4u);
  EXPECT_NE(problems[0].find("width"), std::string::npos);
  EXPECT_NE(problems[1].find("rejectionEpsilon"), std::string::npos);
  EXPECT_NE(problems[2].find("clampBound"), std::string::npos);
  EXPECT_NE(problems[3].find("interleave"), std::string::npos);
  EXPECT_THROW(requireValidSettings(s), std::invalid_argument);
}

TEST(Settings, InfiniteClampBoundIsValid) {
  Settings s;
  s.clampBound = kInfinity;
  EXPECT_TRUE(validateSettings(s).empty());
}

TEST(Settings, NamesRoundTrip) {
  for (Method m : {Method::Reference, Method::Vpl, Method::VplKK, Method::Vsl}) {
    Method parsed{};
    ASSERT_TRUE(parseMethod(toString(m), parsed));
    EXPECT_EQ(parsed, m);
  }
  Method unused{};
  EXPECT_FALSE(parseMethod("vpls", unused));
}

// auto keeps cube maps up to 2^23 triangles x VPLs (the crossover measured in docs/benchmarks.md "VPL visibility:
// auto") and leaves an explicit choice alone.
TEST(Settings, AutoVisibilityPicksCubeMapsOnSmallScenesOnly) {
  EXPECT_EQ(Settings{}.visibility, VisibilityMethod::Auto);
  EXPECT_EQ(resolveVisibility(VisibilityMethod::Auto, 32, 1024), VisibilityMethod::Cube);
  EXPECT_EQ(resolveVisibility(VisibilityMethod::Auto, 32768, 256), VisibilityMethod::Cube);  // exactly 2^23
  EXPECT_EQ(resolveVisibility(VisibilityMethod::Auto, 32769, 256), VisibilityMethod::Ism);
  EXPECT_EQ(resolveVisibility(VisibilityMethod::Auto, 110342, 256), VisibilityMethod::Ism);
  EXPECT_EQ(resolveVisibility(VisibilityMethod::Auto, 110342, 0), VisibilityMethod::Cube);
  EXPECT_EQ(resolveVisibility(VisibilityMethod::Cube, 110342, 256), VisibilityMethod::Cube);
  EXPECT_EQ(resolveVisibility(VisibilityMethod::Ism, 32, 4), VisibilityMethod::Ism);
}

// b relative to the scene: B / diagonal^2, and nothing when B is 0; a tiny scene cannot overflow it.
TEST(Settings, RelativeClampBoundScalesWithTheScene) {
  Settings s;
  s.clampBound = 7.0f;
  resolveClampBound(s, 2.0f);
  EXPECT_EQ(s.clampBound, 7.0f);
  s.clampBoundRelative = 20.0f;
  resolveClampBound(s, 0.9602f);
  EXPECT_NEAR(s.clampBound, 20.0 / (0.9602 * 0.9602), 1e-3);
  resolveClampBound(s, 836.0f);
  EXPECT_NEAR(s.clampBound, 20.0 / (836.0 * 836.0), 1e-9);
  resolveClampBound(s, 0.0f);
  EXPECT_TRUE(std::isfinite(s.clampBound));
  EXPECT_TRUE(validateSettings(s).empty());
}

}  // namespace vplab
