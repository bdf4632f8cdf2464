// Clusters of removed particles under single linkage.
#include "assessment/removed_lumps.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace acdr {
namespace {

std::vector<Eigen::Vector3f> block(int nx, int ny, int nz, float h, const Eigen::Vector3f& at) {
  std::vector<Eigen::Vector3f> p;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) p.push_back(at + h * Eigen::Vector3f(i, j, k));
  return p;
}

TEST(RemovedLumps, NothingRemovedIsNoLump) {
  const LumpStats s = removed_lumps({}, 1e-3);
  EXPECT_EQ(s.particles, 0);
  EXPECT_EQ(s.clusters, 0);
  EXPECT_EQ(s.lump_fraction(), 0.0);
}

TEST(RemovedLumps, APieceOfTheLatticeIsOneLumpAndStraysAreNot) {
  const float h = 2e-3f;
  std::vector<Eigen::Vector3f> p = block(3, 2, 2, h, Eigen::Vector3f::Zero());  // 12
  const std::vector<Eigen::Vector3f> second = block(2, 2, 2, h, Eigen::Vector3f(0.05f, 0, 0));
  p.insert(p.end(), second.begin(), second.end());  // 8: a cluster, not a lump
  p.emplace_back(0.0f, 0.03f, 0.0f);                // single
  p.emplace_back(0.0f, 0.03f + 2.9e-3f, 0.0f);      // within 1.5 h of it: a pair
  const LumpStats s = removed_lumps(p, 1.5 * h);
  EXPECT_EQ(s.particles, 22);
  EXPECT_EQ(s.clusters, 3);
  EXPECT_EQ(s.lumps, 1);
  EXPECT_EQ(s.in_lumps, 12);
  EXPECT_EQ(s.largest, 12);
  EXPECT_DOUBLE_EQ(s.lump_fraction(), 12.0 / 22.0);
}

TEST(RemovedLumps, LinkIsAStrictDistanceAndChainsJoin) {
  // A chain with gaps just under the link is one cluster; one gap just over splits it.
  std::vector<Eigen::Vector3f> chain;
  for (int i = 0; i < 20; ++i) chain.emplace_back(0.99e-3f * i, 0.0f, 0.0f);
  EXPECT_EQ(removed_lumps(chain, 1e-3).clusters, 1);
  for (int i = 10; i < 20; ++i) chain[i].x() += 0.02e-3f;
  const LumpStats s = removed_lumps(chain, 1e-3);
  EXPECT_EQ(s.clusters, 2);
  EXPECT_EQ(s.lumps, 2);
  EXPECT_EQ(s.in_lumps, 20);
  // Negative coordinates and particles far apart are handled.
  std::vector<Eigen::Vector3f> far = {{-0.2f, -0.2f, -0.2f}, {0.2f, 0.2f, 0.2f}};
  EXPECT_EQ(removed_lumps(far, 1e-3).clusters, 2);
}

}  // namespace
}  // namespace acdr
