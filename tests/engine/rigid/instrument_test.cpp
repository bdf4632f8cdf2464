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

// The straight rongeur of the measurements (docs/anatomy.md): 3 mm wide, 6 mm long jaws, each
// 1 mm deep with a 0.4 mm wall, opening 50 degrees, on an 80 mm shaft.
InstrumentConfig straight_rongeur() {
  InstrumentConfig c;
  c.shape = InstrumentShape::kRongeur;
  c.shaft_length_m = 0.08;
  c.jaw_length_m = 6e-3;
  c.jaw_width_m = 3e-3;
  c.jaw_depth_m = 1e-3;
  c.jaw_wall_m = 0.4e-3;
  c.jaw_opening_rad = 50.0 * std::numbers::pi / 180.0;
  return c;
}

TEST(Instrument, RongeurJawsCloseAboutTheHingeAndEncloseTheBite) {
  InstrumentConfig c = straight_rongeur();
  InstrumentGeometry g(c);
  ASSERT_EQ(g.local_colliders().size(), 3u);  // two jaws and the shaft
  EXPECT_EQ(g.local_colliders()[2].kind, ColliderKind::kCapsule);
  EXPECT_NEAR(g.working_point().z(), -0.083, 1e-12);
  // Closed, the jaws' plates stand parallel to the shaft at +-(depth + wall / 2).
  const Pose up = g.jaw_pose(0, 1.0), down = g.jaw_pose(1, 1.0);
  EXPECT_NEAR(up.position.x(), 1.2e-3, 1e-12);
  EXPECT_NEAR(down.position.x(), -1.2e-3, 1e-12);
  EXPECT_NEAR(up.position.z(), -0.083, 1e-12);
  // Open, each turns half the opening away from the axis: its end at 6 mm * sin(25 deg) out.
  const Pose open = g.jaw_pose(0, 0.0);
  const Vec3 end_inner = open.position + open.orientation * Vec3(-0.2e-3, 0, -3e-3);
  EXPECT_NEAR(end_inner.x(), 6e-3 * std::sin(25.0 * std::numbers::pi / 180.0) +
                                 1e-3 * std::cos(25.0 * std::numbers::pi / 180.0), 1e-9);
  // Between the closed jaws: inside the 2 x 3 x 6 mm bite, not beyond its faces or its end.
  EXPECT_TRUE(g.between_jaws(Vec3(0.9e-3, 1.4e-3, -0.0855), 1.0));
  EXPECT_FALSE(g.between_jaws(Vec3(1.1e-3, 0, -0.083), 1.0));
  EXPECT_FALSE(g.between_jaws(Vec3(0, 1.6e-3, -0.083), 1.0));
  EXPECT_FALSE(g.between_jaws(Vec3(0, 0, -0.0865), 1.0));
  EXPECT_FALSE(g.between_jaws(Vec3(0, 0, -0.0795), 1.0));
  // Open, the wedge between the jaws takes in more.
  EXPECT_TRUE(g.between_jaws(Vec3(2.5e-3, 0, -0.085), 0.0));
  // Closing, the jaws' plates move toward the axis: the +x jaw's centre at -x speed.
  std::vector<Collider> world;
  g.world_colliders(Pose{}, Vec3::Zero(), Vec3::Zero(), world, 0.5, 5.0);
  EXPECT_LT(world[0].linear_velocity_m_s.x(), 0.0);
  EXPECT_GT(world[1].linear_velocity_m_s.x(), 0.0);
  // Its velocity is that of a point turning about the hinge.
  const Vec3 w0 = g.jaw_angular_velocity(0, 5.0);
  EXPECT_NEAR((world[0].linear_velocity_m_s - w0.cross(world[0].pose.position - g.hinge())).norm(),
              0.0, 1e-12);
  // Other shapes ignore the closure.
  InstrumentConfig cup;
  cup.shape = InstrumentShape::kCupCurette;
  EXPECT_FALSE(InstrumentGeometry(cup).between_jaws(Vec3(0, 0, -0.082), 1.0));
}

TEST(Instrument, AngledJawsLieOnTheirBentAxis) {
  InstrumentConfig c = straight_rongeur();
  const InstrumentGeometry straight(c);
  const double b = 30.0 * std::numbers::pi / 180.0;
  c.jaw_angle_rad = b;
  const InstrumentGeometry bent(c);
  const Vec3 axis(std::sin(b), 0.0, -std::cos(b));  // the jaws' axis, from the hinge
  const Vec3 side(std::cos(b), 0.0, std::sin(b));   // across it, toward the +x jaw
  // The working point: 3 mm down the bent axis from the hinge at the shaft's tip.
  EXPECT_NEAR((bent.working_point() - (bent.hinge() + 3e-3 * axis)).norm(), 0.0, 1e-15);
  // Closed, each plate's centre stands depth + wall / 2 off the bent axis, half a jaw down it,
  // and the colliders the particles meet are there too.
  std::vector<Collider> world;
  bent.world_colliders(Pose{}, Vec3::Zero(), Vec3::Zero(), world, 1.0, 0.0);
  ASSERT_EQ(world.size(), 3u);
  for (int k = 0; k < 2; ++k) {
    const double s = k == 0 ? 1.0 : -1.0;
    const Vec3 expected = bent.hinge() + 3e-3 * axis + s * 1.2e-3 * side;
    EXPECT_NEAR((bent.jaw_pose(k, 1.0).position - expected).norm(), 0.0, 1e-15) << k;
    EXPECT_NEAR((world[k].pose.position - expected).norm(), 0.0, 1e-15) << k;
    // The plate's long side along the bent axis.
    EXPECT_NEAR((world[k].pose.orientation * Vec3::UnitZ() - (-axis)).norm(), 0.0, 1e-12) << k;
  }
  // The bite lies along the bent axis: inside near its end, outside where straight jaws
  // would hold it.
  EXPECT_TRUE(bent.between_jaws(bent.hinge() + 5.5e-3 * axis + 0.9e-3 * side, 1.0));
  EXPECT_FALSE(bent.between_jaws(bent.hinge() + Vec3(0, 0, -5.5e-3), 1.0));
  EXPECT_TRUE(straight.between_jaws(straight.hinge() + Vec3(0, 0, -5.5e-3), 1.0));
  // Opened by the bend's own size, the -x jaw lies along the shaft and the +x jaw at twice the
  // bend: the inner faces' directions.
  c.jaw_opening_rad = 2.0 * b;
  const InstrumentGeometry wide(c);
  EXPECT_NEAR((wide.jaw_pose(1, 0.0).orientation * Vec3::UnitZ() - Vec3::UnitZ()).norm(), 0.0, 1e-12);
  const Vec3 far = wide.jaw_pose(0, 0.0).orientation * Vec3::UnitZ();
  EXPECT_NEAR(std::acos(far.dot(Vec3::UnitZ())), 2.0 * b, 1e-12);
  EXPECT_LT(far.x(), 0.0);  // its hinge end up and to -x: the jaw's end leans to +x
  // Straight jaws are where they were: the bend of 0 changes nothing.
  c.jaw_angle_rad = 0.0;
  c.jaw_opening_rad = 50.0 * std::numbers::pi / 180.0;
  const InstrumentGeometry again(c);
  for (int k = 0; k < 2; ++k)
    for (double closure : {0.0, 0.4, 1.0}) {
      EXPECT_EQ(again.jaw_pose(k, closure).position, straight.jaw_pose(k, closure).position);
      EXPECT_EQ(again.jaw_pose(k, closure).orientation.coeffs(),
                straight.jaw_pose(k, closure).orientation.coeffs());
    }
  EXPECT_NEAR(again.working_point().z(), -0.083, 1e-15);
}

}  // namespace
}  // namespace acdr
