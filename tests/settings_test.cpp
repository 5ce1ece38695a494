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

}  // namespace vplab
