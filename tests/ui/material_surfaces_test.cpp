// The surface cache extracts a material again only when its particles moved.
#include "ui/material_surfaces.hpp"

#include <gtest/gtest.h>

namespace acdr {
namespace {

TEST(MaterialSurfaceCache, ReusesASurfaceUntilItsParticlesMove) {
  MaterialSurfaceCache cache;
  std::vector<Eigen::Vector3f> a = {{0, 0, 0}, {1e-3f, 0, 0}};
  const std::vector<Eigen::Vector3f> b = {{0, 0, 0.01f}};
  bool reused = true;
  const std::size_t triangles = cache.surface(1, a, 1e-3f, &reused).indices.size();
  EXPECT_FALSE(reused);
  EXPECT_GT(triangles, 0u);
  cache.surface(2, b, 1e-3f, &reused);
  EXPECT_FALSE(reused);
  const std::uint64_t hash_a = cache.hash(1);
  EXPECT_NE(hash_a, 0u);
  EXPECT_EQ(cache.surface(1, a, 1e-3f, &reused).indices.size(), triangles);
  EXPECT_TRUE(reused);
  EXPECT_EQ(cache.extractions(), 2u);
  a[1].x() += 1e-6f;  // moved: extracted again, with a new hash
  cache.surface(1, a, 1e-3f, &reused);
  EXPECT_FALSE(reused);
  EXPECT_NE(cache.hash(1), hash_a);
  EXPECT_EQ(cache.extractions(), 3u);
  EXPECT_EQ(cache.hash(7), 0u);
}

}  // namespace
}  // namespace acdr
