// Tests of ui/sample_scene: the requested number of particles, all inside the box cavity.
#include "ui/sample_scene.hpp"

#include <gtest/gtest.h>

namespace acdr {
namespace {

TEST(SampleScene, HoldsTheRequestedParticlesInsideTheBlock) {
  const SampleSceneLayout layout;
  for (int n : {8, 5000, 20000}) {
    const RenderScene scene = make_sample_scene(n);
    ASSERT_EQ(scene.particles.positions.size(), static_cast<std::size_t>(n));
    ASSERT_EQ(scene.particles.colors.size(), static_cast<std::size_t>(n));
    for (const Eigen::Vector3f& p : scene.particles.positions) {
      EXPECT_TRUE((p.array() >= layout.block_min.array() - 1e-6f).all()) << p.transpose();
      EXPECT_TRUE((p.array() <= layout.block_max.array() + 1e-6f).all()) << p.transpose();
    }
    // Neighbours do not overlap: radius at most half the lattice spacing.
    const float dx = (scene.particles.positions[1] - scene.particles.positions[0]).norm();
    EXPECT_LE(2.0f * scene.particles.radius_m, dx * 1.0001f);
  }
  EXPECT_EQ(make_sample_scene(7).meshes.size(), 7u);  // 5 walls, instrument, zone
}

}  // namespace
}  // namespace acdr
