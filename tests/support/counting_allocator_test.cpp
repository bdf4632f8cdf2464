// The counting allocator sees allocations (so a test that finds none is not blind).
#include "tests/support/counting_allocator.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <vector>

namespace acdr::test_support {
namespace {

TEST(CountingAllocator, CountsEachAllocation) {
  // Kept beyond the lambda, so the compiler cannot elide the allocation.
  std::unique_ptr<int> one;
  std::unique_ptr<double[]> many;
  EXPECT_EQ(allocations_during([&] { one = std::make_unique<int>(7); }), 1);
  EXPECT_EQ(allocations_during([&] { many = std::make_unique<double[]>(9); }), 1);
  std::vector<int> v;
  EXPECT_EQ(allocations_during([&] { v.reserve(100); }), 1);
  EXPECT_EQ(allocations_during([&] { v.push_back(1); }), 0);  // within the reserved capacity
}

}  // namespace
}  // namespace acdr::test_support
