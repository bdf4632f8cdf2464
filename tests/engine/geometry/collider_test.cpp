// Signed distances of the collider shapes at points with known answers.
#include "engine/geometry/collider.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

namespace acdr {
namespace {

TEST(SignedDistance, HalfSpaceIsHeightAboveThePlane) {
  Collider c;
  c.kind = ColliderKind::kHalfSpace;
  c.pose.position = Vec3(0, 0, 0.01);
  Vec3 n;
  EXPECT_NEAR(signed_distance(c, Vec3(0.3, -0.2, 0.015), &n), 0.005, 1e-15);
  EXPECT_NEAR((n - Vec3::UnitZ()).norm(), 0.0, 1e-15);
  EXPECT_NEAR(signed_distance(c, Vec3(0, 0, 0.0), &n), -0.01, 1e-15);
}

TEST(SignedDistance, BoxOutsideFaceEdgeAndInside) {
  Collider c;
  c.kind = ColliderKind::kBox;
  c.half_extents_m = Vec3(1, 2, 3);
  c.pose.position = Vec3(10, 0, 0);
  Vec3 n;
  EXPECT_NEAR(signed_distance(c, Vec3(12, 0, 0), &n), 1.0, 1e-12);  // face
  EXPECT_NEAR((n - Vec3::UnitX()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(signed_distance(c, Vec3(12, 3, 0), &n), std::sqrt(2.0), 1e-12);  // edge
  EXPECT_NEAR((n - Vec3(1, 1, 0).normalized()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(signed_distance(c, Vec3(10, 0, 2.5), &n), -0.5, 1e-12);  // inside, near +z face
  EXPECT_NEAR((n - Vec3::UnitZ()).norm(), 0.0, 1e-12);
}

TEST(SignedDistance, RotatedBoxUsesItsLocalFrame) {
  Collider c;
  c.kind = ColliderKind::kBox;
  c.half_extents_m = Vec3(1, 0.1, 0.1);
  c.pose.orientation = Quat(Eigen::AngleAxisd(0.5 * std::numbers::pi, Vec3::UnitZ()));
  Vec3 n;
  // The long axis now runs along world y.
  EXPECT_NEAR(signed_distance(c, Vec3(0, 0.9, 0.2), &n), 0.1, 1e-12);
  EXPECT_NEAR((n - Vec3::UnitZ()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(signed_distance(c, Vec3(0.9, 0, 0), &n), 0.8, 1e-12);
}

TEST(SignedDistance, CapsuleAroundItsSegment) {
  Collider c;
  c.kind = ColliderKind::kCapsule;
  c.radius_m = 0.5;
  c.half_length_m = 2.0;
  Vec3 n;
  EXPECT_NEAR(signed_distance(c, Vec3(1.5, 0, 1.0), &n), 1.0, 1e-12);
  EXPECT_NEAR(signed_distance(c, Vec3(0, 0, 3.5), &n), 1.0, 1e-12);  // beyond the end cap
  EXPECT_NEAR((n - Vec3::UnitZ()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(signed_distance(c, Vec3(0.2, 0, 0), &n), -0.3, 1e-12);
}

TEST(SignedDistance, CupShellWallRimAndHollow) {
  Collider c;
  c.kind = ColliderKind::kCupShell;
  c.radius_m = 2.0;
  c.thickness_m = 0.5;
  Vec3 n;
  // Below the rim: distance to the shell between radii 1.5 and 2.
  EXPECT_NEAR(signed_distance(c, Vec3(0, 0, -3.0), &n), 1.0, 1e-12);
  EXPECT_NEAR((n + Vec3::UnitZ()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(signed_distance(c, Vec3(0, 0, -1.75), &n), -0.25, 1e-12);  // mid-wall
  EXPECT_NEAR(signed_distance(c, Vec3(0, 0, -1.0), &n), 0.5, 1e-12);     // in the hollow
  EXPECT_NEAR((n - Vec3::UnitZ()).norm(), 0.0, 1e-12);                   // pointing inward
  // Above the rim plane: distance to the rim annulus.
  EXPECT_NEAR(signed_distance(c, Vec3(1.75, 0, 0.3), &n), 0.3, 1e-12);
  EXPECT_NEAR(signed_distance(c, Vec3(0, 0, 0.1), &n), std::hypot(1.5, 0.1), 1e-12);
}

// The nucleus sphere-traces particle paths against these distances, which is only safe if they
// never overestimate: check |sd| against brute-force distances to sampled surface points.
TEST(SignedDistance, CupNeverOverestimates) {
  Collider c;
  c.kind = ColliderKind::kCupShell;
  c.radius_m = 2.0;
  c.thickness_m = 0.4;
  for (int k = 0; k < 200; ++k) {
    const Vec3 p(std::sin(k * 1.3) * 3, std::cos(k * 0.7) * 3, std::sin(k * 0.37) * 3);
    const double sd = signed_distance(c, p, nullptr);
    // A point displaced by sd along the normal lies on the surface (|sd'| small).
    Vec3 n;
    signed_distance(c, p, &n);
    const double on = signed_distance(c, p - sd * n, nullptr);
    EXPECT_LT(std::abs(on), 1e-9) << "point " << p.transpose();
  }
}

}  // namespace
}  // namespace acdr
