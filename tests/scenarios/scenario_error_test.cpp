// The printed form of an error.
#include "scenarios/scenario_error.hpp"

#include <gtest/gtest.h>

namespace acdr {
namespace {

TEST(ScenarioError, PrintsFileLinePathMessage) {
  const ScenarioError e{"m.json", 12, 5, "/world/solver/dt_ms", "wrong type (got string \"1\", expected a number in ms)"};
  EXPECT_EQ(e.to_string(), "m.json:12: /world/solver/dt_ms: wrong type (got string \"1\", expected a number in ms)");
}

TEST(ScenarioError, LeavesOutAnEmptyPath) {
  const ScenarioError e{"m.json", 3, 1, "", "malformed JSON at column 1: x"};
  EXPECT_EQ(e.to_string(), "m.json:3: malformed JSON at column 1: x");
  EXPECT_EQ(to_string({e, e}), e.to_string() + "\n" + e.to_string() + "\n");
}

}  // namespace
}  // namespace acdr
