// Edit distance and nearest-key suggestions.
#include "scenarios/key_suggestion.hpp"

#include <gtest/gtest.h>

namespace acdr {
namespace {

TEST(EditDistance, CountsEditsAndSwaps) {
  EXPECT_EQ(edit_distance("", ""), 0);
  EXPECT_EQ(edit_distance("abc", ""), 3);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3);
  EXPECT_EQ(edit_distance("mass_g", "mas_g"), 1);
  EXPECT_EQ(edit_distance("spacing_mm", "spacnig_mm"), 1);  // adjacent swap
  EXPECT_EQ(edit_distance("Touch", "touch"), 0);            // case ignored
}

TEST(EditDistance, LongInputsAreBounded) {
  const std::string a(100000, 'a');
  EXPECT_LE(edit_distance(a, "abc"), 256);
}

TEST(NearestKey, SuggestsTyposAndMissingUnits) {
  const std::vector<std::string> keys = {"spacing_mm", "spacing_m", "bond_radius_factor", "materials"};
  EXPECT_EQ(nearest_key("spacng_mm", keys), "spacing_mm");
  EXPECT_EQ(nearest_key("spacing", keys), "spacing_mm");
  EXPECT_EQ(nearest_key("material", keys), "materials");
  EXPECT_EQ(nearest_key("bond_radius", keys), "bond_radius_factor");
}

TEST(NearestKey, StaysQuietForUnrelatedKeys) {
  const std::vector<std::string> keys = {"spacing_mm", "materials"};
  EXPECT_FALSE(nearest_key("colour", keys).has_value());
  EXPECT_FALSE(nearest_key("", keys).has_value());
  EXPECT_FALSE(nearest_key("x", {"y"}).has_value());
}

}  // namespace
}  // namespace acdr
