// Contacts only push, and the set of touching particles follows the solution: a cup drawn
// through the box block while it turns feels a force without a step-to-step alternation.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "engine/nucleus/nucleus.hpp"
#include "engine/nucleus/nucleus_stages.hpp"
#include "verification/box_block_scene.hpp"

namespace acdr {
namespace {

// The nucleus's force on a 3 mm cup (0.4 mm wall, its opening tilted 135 degrees from +z
// about y) that starts 1 mm above the block's top, moves 20 mm/s along x and 10 mm/s down
// and turns 2 rad/s about y, one value per 1 ms step.
std::vector<Vec3> turning_cup_force(int steps) {
  BoxBlockScene scene = make_box_block_scene();
  Nucleus n(scene.nucleus, scene.solver, scene.gravity, scene.statics);
  Collider cup;
  cup.kind = ColliderKind::kCupShell;
  cup.body = 0;
  cup.radius_m = 1.5e-3;
  cup.thickness_m = 0.4e-3;
  cup.pose.position = Vec3(0.0075, 0.010, 0.011);
  cup.pose.orientation = Quat(Eigen::AngleAxisd(0.75 * std::numbers::pi, Vec3::UnitY()));
  cup.linear_velocity_m_s = Vec3(0.02, 0.0, -0.01);
  cup.angular_velocity_rad_s = Vec3(0.0, 2.0, 0.0);
  const Quat turn_per_step(Eigen::AngleAxisd(2.0e-3, Vec3::UnitY()));
  BodyReaction reaction;
  std::vector<Vec3> force;
  for (int s = 0; s < steps; ++s) {
    NumericalReport r;
    reaction.reference_point = cup.pose.position;
    n.step(1e-3, std::span<const Collider>(&cup, 1), std::span<BodyReaction>(&reaction, 1), r);
    EXPECT_TRUE(r.ok) << r.stage << " at step " << s;
    force.push_back(reaction.force_N);
    cup.pose.position += 1e-3 * cup.linear_velocity_m_s;
    cup.pose.orientation = (turn_per_step * cup.pose.orientation).normalized();
  }
  return force;
}

// The part of the force that alternates from step to step (a quarter of the second
// difference: the amplitude a of a pure +-a pattern) is small beside the force, over the
// second half of the 400 steps (the cup 2-4 mm into the block). When a particle at the
// contact distance that was receding by a hair was left free for a step and caught again
// the next, it was 4.5 % of the force here (and a third of it along module 02's expert
// sweep); with the contact held and let go only when it pulls, 0.6 %.
TEST(NucleusContacts, ATurningCupFeelsNoStepToStepAlternation) {
  const std::vector<Vec3> f = turning_cup_force(400);
  double alternation2 = 0.0, force2 = 0.0;
  for (std::size_t k = 200; k + 1 < f.size(); ++k) {
    alternation2 += ((f[k + 1] - 2.0 * f[k] + f[k - 1]) / 4.0).squaredNorm();
    force2 += f[k].squaredNorm();
  }
  const double ratio = std::sqrt(alternation2 / force2);
  std::printf("  turning cup: RMS force %.4f N, step-to-step alternation %.2f %% of it\n",
              std::sqrt(force2 / 199.0), 100.0 * ratio);
  EXPECT_GT(force2, 199.0 * 1e-4);  // the cup is in the material (RMS above 10 mN)
  EXPECT_LT(ratio, 0.02);
}

// A particle between two walls that face each other (the cup closing on the bone) is held by
// the first wall only: both targets cannot hold, and solved together they asked for a large
// velocity along the gap (a 6-7 N force alternating on the cup in module 02). A wall at a
// right angle to the first is a corner, and both hold.
TEST(NucleusContacts, FacingWallsHoldAParticleByTheFirstOnly) {
  StepContacts contacts;
  contacts.count.resize(1);
  contacts.e.resize(1);
  contacts.v.resize(1);
  const Vec3 floor(0.0, 0.0, 1.0);
  const Vec3 cup_above = Vec3(0.0, 0.3, -1.0).normalized();  // 107 degrees from the floor's
  const Vec3 side(1.0, 0.0, 0.0);
  {
    const Vec3 n[2] = {floor, cup_above};
    const double t[2] = {0.0, 0.01};
    EXPECT_EQ(nucleus::set_contact_constraint(contacts, 0, n, t, 2), 1u);
    EXPECT_EQ(contacts.count[0], 1);
    EXPECT_NEAR(contacts.v[0].z(), 0.0, 1e-15);
    EXPECT_LT(contacts.v[0].norm(), 1e-12);
  }
  {
    const Vec3 n[3] = {floor, side, cup_above};
    const double t[3] = {0.0, -0.002, 0.01};
    EXPECT_EQ(nucleus::set_contact_constraint(contacts, 0, n, t, 3), 3u);
    EXPECT_EQ(contacts.count[0], 2);
    EXPECT_NEAR(contacts.v[0].dot(floor), 0.0, 1e-15);
    EXPECT_NEAR(contacts.v[0].dot(side), -0.002, 1e-15);
  }
}

}  // namespace
}  // namespace acdr
