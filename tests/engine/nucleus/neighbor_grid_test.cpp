// The hashed grid finds exactly the pairs a brute-force search finds, open and periodic.
#include "engine/nucleus/neighbor_grid.hpp"

#include <algorithm>
#include <random>
#include <set>

#include <gtest/gtest.h>

namespace acdr {
namespace {

std::set<std::pair<int, int>> grid_pairs(const std::vector<Vec3>& x, double R,
                                         std::array<bool, 3> periodic, const Vec3& lo,
                                         const Vec3& hi) {
  NeighborGrid grid;
  grid.reserve(x.size());
  grid.build(x, R, periodic, lo, hi);
  std::set<std::pair<int, int>> out;
  for (std::size_t i = 0; i < x.size(); ++i)
    grid.for_each_candidate(i, [&](std::size_t j) {
      if (j <= i) return;
      Vec3 d = x[j] - x[i];
      for (int a = 0; a < 3; ++a)
        if (periodic[a]) d[a] -= (hi[a] - lo[a]) * std::round(d[a] / (hi[a] - lo[a]));
      if (d.norm() < R) {
        const bool fresh = out.insert({int(i), int(j)}).second;
        EXPECT_TRUE(fresh) << "pair visited twice";
      }
    });
  return out;
}

std::set<std::pair<int, int>> brute_pairs(const std::vector<Vec3>& x, double R,
                                          std::array<bool, 3> periodic, const Vec3& lo,
                                          const Vec3& hi) {
  std::set<std::pair<int, int>> out;
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = i + 1; j < x.size(); ++j) {
      Vec3 d = x[j] - x[i];
      for (int a = 0; a < 3; ++a)
        if (periodic[a]) d[a] -= (hi[a] - lo[a]) * std::round(d[a] / (hi[a] - lo[a]));
      if (d.norm() < R) out.insert({int(i), int(j)});
    }
  return out;
}

TEST(NeighborGrid, MatchesBruteForceInAnOpenDomain) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.01, 0.01);
  std::vector<Vec3> x(600);
  for (auto& p : x) p = Vec3(u(rng), u(rng), u(rng) * 0.3);
  x.push_back(Vec3(5.0, 5.0, 5.0));  // far away material still hashes
  const double R = 2.1e-3;
  EXPECT_EQ(grid_pairs(x, R, {false, false, false}, Vec3::Zero(), Vec3::Zero()),
            brute_pairs(x, R, {false, false, false}, Vec3::Zero(), Vec3::Zero()));
}

TEST(NeighborGrid, MatchesBruteForceWithPeriodicAxes) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Vec3 lo(0, 0, 0), hi(0.008, 0.005, 0.004);  // 5 mm / 2.1 mm: 2 cells, wraps onto itself
  std::vector<Vec3> x(300);
  for (auto& p : x) p = Vec3(u(rng) * hi.x(), u(rng) * hi.y(), u(rng) * hi.z());
  const double R = 2.1e-3;
  for (auto per : {std::array<bool, 3>{true, true, false}, std::array<bool, 3>{true, true, true}})
    EXPECT_EQ(grid_pairs(x, R, per, lo, hi), brute_pairs(x, R, per, lo, hi));
}

}  // namespace
}  // namespace acdr
