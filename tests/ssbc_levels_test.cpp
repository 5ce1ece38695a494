#include <gtest/gtest.h>

#include "renderer/gl/ssbc_pass.h"

namespace vplab {
namespace {

// The tap buffers hold every level of the full mip chain one after another (shaders/common/ssbc_levels.glsl): as many
// levels as GL gives a 2D texture of that size, each max(1, size >> level) texels wide and high.
TEST(SsbcTapLevels, EveryLevelOfTheMipChainFollowsTheLast) {
  const std::vector<int> bases = ssbcTapLevelBases(640, 480);
  ASSERT_EQ(bases.size(), 11u);  // 10 levels: 640x480 down to 1x1
  EXPECT_EQ(bases[0], 0);
  EXPECT_EQ(bases[1], 640 * 480);
  EXPECT_EQ(bases[2], 640 * 480 + 320 * 240);
  EXPECT_EQ(bases[10] - bases[9], 1);     // level 9: 1x1
  EXPECT_EQ(bases[9] - bases[8], 2 * 1);  // level 8: 2x1
  const std::vector<int> thin = ssbcTapLevelBases(1, 5);
  ASSERT_EQ(thin.size(), 4u);  // 1x5, 1x2, 1x1
  EXPECT_EQ(thin.back(), 5 + 2 + 1);
}

}  // namespace
}  // namespace vplab
