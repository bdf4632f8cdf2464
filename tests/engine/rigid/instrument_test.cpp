// Instrument geometry and the derived yield moment.
#include "engine/rigid/instrument.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include <numbers>

namespace acdr {
namespace {

TEST(Instrument, YieldMomentOfRoundShaft) {
  InstrumentConfig c;
  c.shaft_diameter_m = 2e-3;
  c.yield_stress_Pa = 500e6;
  // sigma * pi * d^3 / 32 = 500e6 * pi * 8e-9 / 32 = 0.3927 N·m
  EXPECT_NEAR(c.yield_moment_Nm(), 0.125 * std::numbers::pi, 1e-12);
  InstrumentGeometry g(c);
  EXPECT_NEAR(g.warning_moment_Nm(), 0.5 * c.yield_moment_Nm(), 1e-15);
}

TEST(Instrument, PrismBladeHangsBelowTheShaft) {
  InstrumentConfig c;
  c.shape = InstrumentShape::kPrism;
  c.shaft_length_m = 0.08;
  c.blade_size_m = Vec3(0.01, 0.006, 0.002);
  InstrumentGeometry g(c);
  ASSERT_EQ(g.local_colliders().size(), 2u);
  const Collider& blade = g.local_colliders()[0];
  EXPECT_EQ(blade.kind, ColliderKind::kBox);
  EXPECT_NEAR(blade.pose.position.z(), -0.081, 1e-12);
  // Placed at a grip pose moving at v, every collider moves with the body.
  std::vector<Collider> world;
  Pose grip;
  grip.position = Vec3(0, 0, 0.11);
  g.world_colliders(grip, Vec3(0.1, 0, 0), Vec3(0, 0, 1), world);
  EXPECT_NEAR(world[0].pose.position.z(), 0.029, 1e-12);
  EXPECT_NEAR(world[0].linear_velocity_m_s.x(), 0.1, 1e-12);
}

TEST(Instrument, CupOpensSideways) {
  InstrumentConfig c;
  c.shape = InstrumentShape::kCupCurette;
  InstrumentGeometry g(c);
  const Collider& cup = g.local_colliders()[0];
  EXPECT_EQ(cup.kind, ColliderKind::kCupShell);
  // The cup's local +z (its opening) points along body +x.
  EXPECT_NEAR((cup.pose.orientation * Vec3::UnitZ() - Vec3::UnitX()).norm(), 0.0, 1e-12);
}

TEST(Instrument, AngledCupOpensBackTowardTheGrip) {
  InstrumentConfig c;
  c.shape = InstrumentShape::kCupCurette;
  c.cup_opening_angle_rad = 0.75 * M_PI;  // 135 deg from the tip direction (-z)
  InstrumentGeometry g(c);
  const Collider& cup = g.local_colliders()[0];
  const Vec3 opening = cup.pose.orientation * Vec3::UnitZ();
  // Half sideways (+x), half back toward the grip (+z), and 135 deg from the tip direction.
  EXPECT_NEAR((opening - Vec3(std::sqrt(0.5), 0.0, std::sqrt(0.5))).norm(), 0.0, 1e-12);
  EXPECT_NEAR(std::acos(opening.dot(-Vec3::UnitZ())), 0.75 * M_PI, 1e-12);
  // The cup stays where the straight one is: below the shaft end, touching it.
  InstrumentConfig straight = c;
  straight.cup_opening_angle_rad = 0.5 * M_PI;
  EXPECT_EQ(cup.pose.position, InstrumentGeometry(straight).local_colliders()[0].pose.position);
}

}  // namespace
}  // namespace acdr
