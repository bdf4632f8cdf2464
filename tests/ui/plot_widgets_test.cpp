// Tests of ui/plot_widgets: round tick values for the axes.
#include "ui/plot_widgets.hpp"

#include <gtest/gtest.h>

namespace acdr {
namespace {

TEST(PlotWidgets, NiceTicksAreRoundAndCoverTheRange) {
  EXPECT_EQ(nice_ticks(0, 100, 5), (std::vector<float>{0, 20, 40, 60, 80, 100}));
  EXPECT_EQ(nice_ticks(0, 3.3f, 4), (std::vector<float>{0, 1, 2, 3}));
  // 0.0042 / 4 = 0.00105 per tick: the next round step is 0.002.
  const auto small = nice_ticks(0.0f, 0.0042f, 4);
  ASSERT_EQ(small.size(), 3u);
  EXPECT_FLOAT_EQ(small[1] - small[0], 0.002f);
  EXPECT_TRUE(nice_ticks(1, 1, 4).empty());
  for (float t : nice_ticks(-7, 13, 5)) EXPECT_EQ(std::fmod(t, 5.0f), 0.0f);
}

}  // namespace
}  // namespace acdr
