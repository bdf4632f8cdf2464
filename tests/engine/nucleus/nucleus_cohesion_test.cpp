// Re-bonding (cohesion): two pieces of a cohesive material laid against each other at rest
// join with bonds made at their current distance (no energy stored, the piece then holds
// together under a pull it could not take before); pieces pulled apart faster than the rest
// speed never join; a material without the option makes none; a step with re-bonding on
// allocates nothing.
#include <cmath>

#include <gtest/gtest.h>

#include "engine/nucleus/nucleus.hpp"
#include "tests/engine/nucleus/nucleus_test_scenes.hpp"
#include "tests/support/counting_allocator.hpp"
#include "verification/box_block_scene.hpp"

namespace acdr {
namespace {

constexpr double kH = 1e-3;

/// Two 2 x 2 x 2 cubes of bonded particles on a 1 mm lattice, side by side along x with one
/// spacing between their facing layers (touching, unbonded), no gravity, at rest.
using test::TwoPieces;

TwoPieces two_pieces(double rebond_time_s) {
  MaterialConfig m;
  m.rebond_time_s = rebond_time_s;
  m.rebond_speed_m_s = 1e-3;
  return test::two_pieces(m, kH, kH);
}

void run(Nucleus& n, int steps) {
  for (int s = 0; s < steps; ++s) {
    NumericalReport r;
    n.step(1e-3, {}, {}, r);
    ASSERT_TRUE(r.ok) << r.stage;
  }
}

/// Re-formed bonds that join the left piece to the right one.
int bonds_between(const Nucleus& n, const TwoPieces& s) {
  int count = 0;
  const auto ij = n.reformed_bond_particles();
  const auto intact = n.reformed_bond_intact();
  for (std::size_t b = 0; b < intact.size(); ++b) {
    if (!intact[b]) continue;
    const bool i_left = ij[2 * b] < static_cast<int>(s.left.size());
    const bool j_left = ij[2 * b + 1] < static_cast<int>(s.left.size());
    count += i_left != j_left;
  }
  return count;
}

Vec3 centre(const Nucleus& n, const std::vector<int>& piece) {
  Vec3 c = Vec3::Zero();
  for (const int i : piece) c += n.positions()[i];
  return c / static_cast<double>(piece.size());
}

TEST(NucleusCohesion, TouchingPiecesAtRestJoinWithoutStoringEnergy) {
  const TwoPieces s = two_pieces(0.01);
  Nucleus n(s.config, s.solver, Vec3::Zero(), {}, s.setup);
  run(n, 5);  // not yet rested 10 ms
  EXPECT_EQ(n.reformed_bond_count(), 0u);
  const double before = n.mechanical_energy_J();
  run(n, 15);
  // The facing layers (4 particles each) are 1 mm apart: 4 axial and 8 diagonal pairs.
  EXPECT_EQ(bonds_between(n, s), 12);
  EXPECT_EQ(n.reformed_bond_count(), 12u);
  EXPECT_EQ(n.intact_reformed_bond_count(), 12u);
  // Made at their current length: the energy did not rise.
  EXPECT_LE(n.mechanical_energy_J(), before + 1e-15);
  // Joined, the pieces hold together under a pull the 12 bonds can take (each breaks at
  // k delta_max = 1.5 mN; 4 x 0.5 mN on each side).
  for (const int i : s.left) n.external_forces()[i] = Vec3(-0.25e-3, 0, 0);
  for (const int i : s.right) n.external_forces()[i] = Vec3(0.25e-3, 0, 0);
  run(n, 300);
  EXPECT_EQ(bonds_between(n, s), 12);
  EXPECT_LT((centre(n, s.right) - centre(n, s.left)).x(), 2.1 * kH);
}

TEST(NucleusCohesion, PiecesPulledApartFasterThanTheRestSpeedDoNotJoin) {
  const TwoPieces s = two_pieces(0.01);
  Nucleus n(s.config, s.solver, Vec3::Zero(), {}, s.setup);
  // 20 mN per piece apart: the pieces separate faster than 1 mm/s from the first step.
  for (const int i : s.left) n.external_forces()[i] = Vec3(-2.5e-3, 0, 0);
  for (const int i : s.right) n.external_forces()[i] = Vec3(2.5e-3, 0, 0);
  double min_rate = 1.0;
  double gap_before = (centre(n, s.right) - centre(n, s.left)).x();
  for (int step = 0; step < 100; ++step) {
    run(n, 1);
    const double gap = (centre(n, s.right) - centre(n, s.left)).x();
    if (gap < 3.5 * kH) min_rate = std::min(min_rate, (gap - gap_before) / 1e-3);
    gap_before = gap;
  }
  EXPECT_GT(min_rate, 1e-3);  // the premise: faster than the rest speed while in reach
  EXPECT_EQ(n.reformed_bond_count(), 0u);
  EXPECT_GT((centre(n, s.right) - centre(n, s.left)).x(), 3.5 * kH);
}

TEST(NucleusCohesion, WithoutTheOptionNoBondIsMade) {
  const TwoPieces s = two_pieces(0.0);
  Nucleus n(s.config, s.solver, Vec3::Zero(), {}, s.setup);
  run(n, 50);
  EXPECT_EQ(n.reformed_bond_count(), 0u);
  EXPECT_TRUE(n.reformed_bond_particles().empty());
}

TEST(NucleusCohesion, ReBondingStepDoesNotAllocate) {
  BoxBlockScene scene = make_box_block_scene(2e-3);
  // Rest reached soon after the blade stops: the cut material still creeps at a few mm/s.
  scene.nucleus.materials[0].rebond_time_s = 0.002;
  scene.nucleus.materials[0].rebond_speed_m_s = 0.02;
  Nucleus n(scene.nucleus, scene.solver, scene.gravity, scene.statics);
  Collider blade = scene.blade;
  blade.linear_velocity_m_s = Vec3(0, 0, -0.1);
  BodyReaction reaction;
  NumericalReport r;
  n.step(1e-3, std::span<const Collider>(&blade, 1), std::span<BodyReaction>(&reaction, 1), r);
  const long before = test_support::heap_allocations();
  for (int s = 0; s < 150; ++s) {
    if (s == 30) blade.linear_velocity_m_s = Vec3::Zero();  // rest: bonds re-form
    blade.pose.position += 1e-3 * blade.linear_velocity_m_s;
    n.step(1e-3, std::span<const Collider>(&blade, 1), std::span<BodyReaction>(&reaction, 1), r);
    ASSERT_TRUE(r.ok) << r.stage;
  }
  EXPECT_EQ(test_support::heap_allocations() - before, 0);
  EXPECT_GT(n.broken_bond_count(), 0u);
  EXPECT_GT(n.reformed_bond_count(), 0u);
}

}  // namespace
}  // namespace acdr
