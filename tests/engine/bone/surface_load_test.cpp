// Contact patches and face tractions become nodal forces that add up to the load.
#include "engine/bone/surface_load.hpp"

#include <gtest/gtest.h>

#include "engine/bone/box_tet_mesh.hpp"

namespace acdr {
namespace {

Vec3 total(const std::vector<double>& f) {
  Vec3 s = Vec3::Zero();
  for (std::size_t i = 0; i < f.size(); i += 3) s += Vec3(f[i], f[i + 1], f[i + 2]);
  return s;
}

class SurfaceLoadOrders : public ::testing::TestWithParam<TetOrder> {};

TEST_P(SurfaceLoadOrders, PatchForcesAddUpAndStayInThePatch) {
  const TetMesh m = make_box_tet_mesh(Vec3::Zero(), Vec3(10e-3, 10e-3, 4e-3), {10, 10, 4});
  const FeSpace space = make_fe_space(m, GetParam());
  const BoundarySurface surface(m);
  std::vector<double> f(3 * space.nodes.size(), 0.0);
  std::vector<std::uint32_t> scratch;
  ContactLoad c;
  c.point_m = Vec3(5e-3, 5e-3, 4.3e-3);  // 0.3 mm above the top face
  c.force_N = Vec3(1.0, 0.0, -20.0);
  c.radius_m = 2e-3;
  ASSERT_TRUE(add_contact_load(space, surface, c, 1e-3, f, scratch));
  EXPECT_LT((total(f) - c.force_N).norm(), 1e-12);
  // Only top-face nodes within the patch (plus an edge's length) are loaded.
  for (std::size_t i = 0; i < space.nodes.size(); ++i) {
    if (Vec3(f[3 * i], f[3 * i + 1], f[3 * i + 2]).norm() == 0.0) continue;
    EXPECT_NEAR(space.nodes[i].z(), 4e-3, 1e-12);
    EXPECT_LT((space.nodes[i] - Vec3(5e-3, 5e-3, 4e-3)).norm(), c.radius_m + 1.5e-3);
  }
  // Too far from the surface: nothing added.
  std::vector<double> g(f.size(), 0.0);
  c.point_m = Vec3(5e-3, 5e-3, 8e-3);
  EXPECT_FALSE(add_contact_load(space, surface, c, 1e-3, g, scratch));
  EXPECT_EQ(total(g).norm(), 0.0);
}

TEST_P(SurfaceLoadOrders, TinyPatchBecomesAPointLoadOnTheNearestFace) {
  const TetMesh m = make_box_tet_mesh(Vec3::Zero(), Vec3(2e-3, 2e-3, 2e-3), {1, 1, 1});
  const FeSpace space = make_fe_space(m, GetParam());
  const BoundarySurface surface(m);
  std::vector<double> f(3 * space.nodes.size(), 0.0);
  std::vector<std::uint32_t> scratch;
  ContactLoad c;
  c.point_m = Vec3(0.0, 0.0, 2e-3);  // exactly on a corner node of the top face
  c.force_N = Vec3(0, 0, -3.0);
  c.radius_m = 1e-9;
  ASSERT_TRUE(add_contact_load(space, surface, c, 1e-3, f, scratch));
  EXPECT_LT((total(f) - c.force_N).norm(), 1e-12);
  // The corner node takes it all (its shape function is 1 there, the others 0).
  std::size_t corner = 0;
  for (std::size_t i = 0; i < m.nodes.size(); ++i)
    if ((m.nodes[i] - c.point_m).norm() < 1e-12) corner = i;
  EXPECT_NEAR(f[3 * corner + 2], -3.0, 1e-12);
}

TEST_P(SurfaceLoadOrders, UniformTractionAddsUpToPressureTimesArea) {
  const TetMesh m = make_box_tet_mesh(Vec3::Zero(), Vec3(3e-3, 2e-3, 1e-3), {3, 2, 1});
  const FeSpace space = make_fe_space(m, GetParam());
  const BoundarySurface surface(m);
  std::vector<double> f(3 * space.nodes.size(), 0.0);
  for (std::size_t k = 0; k < surface.faces().size(); ++k)
    if (surface.face_normal(k).z() > 0.5) add_face_traction(space, surface, k, Vec3(0, 0, -2e6), f);
  EXPECT_NEAR(total(f).z(), -2e6 * 6e-6, 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Bone, SurfaceLoadOrders,
                         ::testing::Values(TetOrder::kLinear, TetOrder::kQuadratic));

}  // namespace
}  // namespace acdr
