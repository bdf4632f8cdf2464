// The static solids of a practice scene: the ground plane and the open box's five walls.
#include "engine/rigid/static_scene.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

namespace acdr {
namespace {

/// Distance from p to the nearest of the colliders (negative inside one).
double nearest(const std::vector<Collider>& colliders, const Vec3& p) {
  double d = std::numeric_limits<double>::infinity();
  for (const Collider& c : colliders) d = std::min(d, signed_distance(c, p, nullptr));
  return d;
}

TEST(StaticScene, OpenBoxWallsEncloseTheCavityAndLeaveTheTopOpen) {
  const Vec3 lo(0, 0, 0), hi(0.03, 0.02, 0.012);
  const double t = 2e-3;
  const auto walls = open_box_walls(lo, hi, t);
  ASSERT_EQ(walls.size(), 5u);
  for (const Collider& w : walls) EXPECT_EQ(w.kind, ColliderKind::kBox);
  // The cavity's centre is as far from the walls as from its nearest face (z: 6 mm).
  EXPECT_NEAR(nearest(walls, 0.5 * (lo + hi)), 0.5 * (hi.z() - lo.z()), 1e-12);
  // Just beyond each face lies wall; above the cavity there is none.
  const Vec3 c = 0.5 * (lo + hi);
  EXPECT_LT(nearest(walls, Vec3(c.x(), c.y(), lo.z() - 0.5 * t)), 0.0);  // floor
  EXPECT_LT(nearest(walls, Vec3(lo.x() - 0.5 * t, c.y(), c.z())), 0.0);  // -x
  EXPECT_LT(nearest(walls, Vec3(hi.x() + 0.5 * t, c.y(), c.z())), 0.0);  // +x
  EXPECT_LT(nearest(walls, Vec3(c.x(), lo.y() - 0.5 * t, c.z())), 0.0);  // -y
  EXPECT_LT(nearest(walls, Vec3(c.x(), hi.y() + 0.5 * t, c.z())), 0.0);  // +y
  EXPECT_GT(nearest(walls, Vec3(c.x(), c.y(), hi.z() + 0.5 * t)), 0.0);  // open top
  // The corners are closed: below a bottom corner of the cavity, and outside a vertical edge.
  EXPECT_LT(nearest(walls, lo - Vec3(0.5 * t, 0.5 * t, 0.5 * t)), 0.0);
  EXPECT_LT(nearest(walls, Vec3(hi.x() + 0.5 * t, hi.y() + 0.5 * t, c.z())), 0.0);
  // Nothing of the walls reaches into the cavity (beyond rounding of centre +- half extent).
  const double eps = 1e-12;
  for (const Collider& w : walls) {
    const Vec3 wmin = w.pose.position - w.half_extents_m, wmax = w.pose.position + w.half_extents_m;
    const bool overlaps =
        (wmin.array() < hi.array() - eps).all() && (wmax.array() > lo.array() + eps).all();
    EXPECT_FALSE(overlaps) << "a wall overlaps the cavity";
  }
}

TEST(StaticScene, BuildsTheDeclaredGroundAndBox) {
  GroundConfig ground;
  OpenBoxConfig box;
  EXPECT_TRUE(build_static_colliders(ground, box).empty());
  ground.enabled = true;
  ground.height_m = -2e-3;
  box.enabled = true;
  box.inner_max_m = Vec3(0.016, 0.01, 0.01);
  const auto all = build_static_colliders(ground, box);
  ASSERT_EQ(all.size(), 6u);
  EXPECT_EQ(all[0].kind, ColliderKind::kHalfSpace);
  EXPECT_EQ(all[0].pose.position.z(), -2e-3);
  const auto walls = open_box_walls(box.inner_min_m, box.inner_max_m, box.wall_thickness_m);
  for (std::size_t i = 0; i < walls.size(); ++i) {
    EXPECT_EQ(all[1 + i].pose.position, walls[i].pose.position);
    EXPECT_EQ(all[1 + i].half_extents_m, walls[i].half_extents_m);
  }
}

}  // namespace
}  // namespace acdr
