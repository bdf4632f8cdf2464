// The assembled World: parts built only when declared, the virtual coupling, forces from the
// nucleus reaching the instrument, rigid contact with the box, and bit-for-bit determinism.
#include "engine/world.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace acdr {
namespace {

/// A small version of the seed's box: 10 x 10 mm cavity, 4 mm of nucleus (400 particles).
WorldConfig small_box(bool with_nucleus = true) {
  WorldConfig c;
  c.ground.enabled = true;
  c.ground.height_m = -2e-3;
  c.box.enabled = true;
  c.box.inner_min_m = Vec3(-5e-3, -5e-3, 0);
  c.box.inner_max_m = Vec3(5e-3, 5e-3, 8e-3);
  c.nucleus.enabled = with_nucleus;
  c.nucleus.spacing_m = 1e-3;
  c.nucleus.materials.push_back(MaterialConfig{});
  c.nucleus.blocks.push_back({Vec3(-5e-3, -5e-3, 0), Vec3(5e-3, 5e-3, 4e-3), 0});
  c.instrument.enabled = true;
  c.instrument.blade_size_m = Vec3(4e-3, 4e-3, 1e-3);
  c.instrument.shaft_length_m = 0.05;
  c.instrument_start.position = Vec3(0, 0, 0.07);
  c.removal.min_m = Vec3(-5e-3, -5e-3, -1e-3);
  c.removal.max_m = Vec3(5e-3, 5e-3, 8e-3);
  return c;
}

DeviceSample at(const Vec3& grip) {
  DeviceSample s;
  s.pose.position = grip;
  return s;
}

TEST(World, BuildsOnlyWhatIsDeclared) {
  WorldConfig c = small_box(false);
  c.box.enabled = false;
  World w(c);
  EXPECT_EQ(w.nucleus(), nullptr);
  EXPECT_EQ(w.static_colliders().size(), 1u);  // the ground only
  World full(small_box());
  ASSERT_NE(full.nucleus(), nullptr);
  EXPECT_EQ(full.static_colliders().size(), 6u);  // ground + five walls
  EXPECT_EQ(full.summary().initial_target, 400);
  EXPECT_EQ(full.last_frame().removed_target, 0);
}

TEST(World, CouplingHoldsTheInstrumentAgainstGravityInFreeSpace) {
  // Without contact, the coupling spring carries the instrument's weight: the steady offset is
  // m*g/ks and the force sent to the user is the weight (once ramped in).
  const WorldConfig c = small_box(false);
  World w(c);
  const Vec3 grip = c.instrument_start.position;
  Frame f;
  for (int i = 0; i < 1500; ++i) f = w.step(at(grip));
  const double weight = c.instrument.mass_kg * kStandardGravity;
  EXPECT_NEAR(grip.z() - f.instrument.position.z(), weight / c.coupling.stiffness_N_m, 2e-6);
  EXPECT_NEAR(f.coupling_force_N.z(), weight, 0.02 * weight);
  EXPECT_NEAR(f.feedback_force_N.z(), -weight, 0.02 * weight);
  EXPECT_LT(f.instrument.position.head<2>().norm(), 1e-6);
}

TEST(World, NucleusPushesBackAndBoxStopsTheBlade) {
  const WorldConfig c = small_box();
  World w(c);
  // Lower the grip steadily so the blade enters the nucleus, then presses on the floor.
  double peak_up = 0;
  Frame f;
  // 25 mm/s down for 0.96 s, then hold with the device 4 mm below the floor.
  for (int i = 0; i < 1400; ++i) {
    const double z = std::max(0.07 - 2.5e-5 * i, 0.051 - 0.004);
    f = w.step(at(Vec3(0, 0, z)));
    peak_up = std::max(peak_up, f.nucleus_force_N.z());
    ASSERT_FALSE(w.failed()) << "numerical trouble at step " << i;
  }
  EXPECT_GT(peak_up, 1e-3) << "the nucleus resisted the blade";
  // The floor holds the blade: the blade bottom stays above z = -0.2 mm.
  const double blade_bottom = f.instrument.position.z() - c.instrument.shaft_length_m -
                              c.instrument.blade_size_m.z();
  EXPECT_GT(blade_bottom, -2e-4);
  EXPECT_GT(f.contact_force_N.z(), 0.5) << "the box floor carries the push";
}

TEST(World, SameInputSameStateBitForBit) {
  auto run = [] {
    World w(small_box());
    for (int i = 0; i < 300; ++i) w.step(at(Vec3(1e-5 * i, 0, 0.07 - 5e-5 * i)));
    return w.state_hash();
  };
  EXPECT_EQ(run(), run());
}

TEST(World, NonFiniteInputIsRejectedAndReported) {
  World w(small_box(false));
  DeviceSample bad = at(Vec3(0, 0, 0.07));
  bad.pose.position.x() = NAN;
  w.step(at(Vec3(0, 0, 0.07)));
  const Frame f = w.step(bad);
  EXPECT_FALSE(f.input_valid);
  EXPECT_TRUE(f.instrument.position.allFinite());
  EXPECT_EQ(f.feedback_force_N, Vec3::Zero());
  std::vector<Event> events;
  w.drain_events(events);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events[0].kind, EventKind::kInputRejected);
}

}  // namespace
}  // namespace acdr
