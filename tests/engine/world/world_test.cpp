// The assembled World: parts built only when declared, the virtual coupling, forces from the
// nucleus reaching the instrument, rigid contact with the box, and bit-for-bit determinism.
#include "engine/world/world.hpp"

#include "engine/world/box_world.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace acdr {
namespace {

/// A small version of the seed's box: 10 x 10 mm cavity, 4 mm of nucleus (400 particles).
WorldConfig small_box(bool with_nucleus = true) {
  BoxWorldOptions o;
  o.nucleus = with_nucleus;
  return make_box_world(o);
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

TEST(World, NucleusWithoutInstrumentReportsItsSolverIterations) {
  WorldConfig c = small_box();
  c.instrument.enabled = false;
  World w(c);
  ASSERT_EQ(w.instrument(), nullptr);
  const Frame& f = w.step(DeviceSample{});
  EXPECT_GT(f.solver_iterations, 0);
  EXPECT_EQ(f.nucleus_force_N, Vec3::Zero());
  EXPECT_EQ(f.coupling_force_N, Vec3::Zero());
  EXPECT_FALSE(w.failed());
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

// Multi-rate: with nucleus_every = 3 the particles step at steps 0, 3, 6, ... over 3 ms, the
// steps between spend no iterations and leave the particles as they were, and the held reaction
// still pushes on the instrument; its mean over the press is near the every-step run's.
TEST(World, MultiRateStepsTheParticlesEveryKthStepAndHoldsTheirReaction) {
  const int k = 3;
  WorldConfig every = small_box();
  every.solver.nucleus_every = k;
  World multi(every);
  World single(small_box());
  auto press = [](int i) { return at(Vec3(0, 0, std::max(0.07 - 2.5e-5 * i, 0.0535))); };
  double multi_sum = 0.0, single_sum = 0.0;
  int pressing = 0, solved = 0;
  for (int i = 0; i < 1000; ++i) {
    const std::uint64_t before = multi.nucleus()->state_hash();
    const Frame& f = multi.step(press(i));
    const Frame& g = single.step(press(i));
    ASSERT_FALSE(multi.failed()) << "numerical trouble at step " << i;
    if (i % k == 0) {
      solved += f.solver_iterations > 0;  // none while every particle sleeps
    } else {
      EXPECT_EQ(f.solver_iterations, 0) << "step " << i;
      EXPECT_EQ(multi.nucleus()->state_hash(), before) << "step " << i;
    }
    if (i >= 700) {  // the blade held in the nucleus, above the floor
      multi_sum += f.nucleus_force_N.z();
      single_sum += g.nucleus_force_N.z();
      ++pressing;
    }
  }
  EXPECT_GT(solved, 200) << "the particles step at every third step";
  EXPECT_NEAR(multi.time_s(), single.time_s(), 1e-12);
  const double multi_mean = multi_sum / pressing, single_mean = single_sum / pressing;
  EXPECT_GT(single_mean, 1e-3) << "the nucleus resists the blade";
  EXPECT_NEAR(multi_mean, single_mean, 0.1 * single_mean);
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

// The device safety rules, each recorded as an event: force clamped to the device
// maximum, NaN input (above), a pose jump, and lost input (the device went silent).
std::vector<Event> kinds_of(World& w, EventKind kind) {
  std::vector<Event> all, out;
  w.drain_events(all);
  for (const Event& e : all)
    if (e.kind == kind) out.push_back(e);
  return out;
}

TEST(WorldSafety, ForceIsClampedToTheDeviceMaximumAndRecorded) {
  World w(small_box(false));
  // Press the blade into the box floor: the coupling spring stretches far beyond 3.3 N.
  double max_sent = 0;
  for (int i = 0; i < 1500; ++i) {
    const Frame& f = w.step(at(Vec3(0, 0, std::max(0.07 - 1e-4 * i, 0.0))));
    max_sent = std::max(max_sent, f.feedback_force_N.norm());
  }
  EXPECT_LE(max_sent, 3.3 + 1e-9);
  EXPECT_GT(max_sent, 3.2);
  const auto clamped = kinds_of(w, EventKind::kForceClamped);
  ASSERT_FALSE(clamped.empty());
  EXPECT_GT(clamped[0].value, 3.3);  // the force that was asked for
}

// Steps with a steady push (the device held 4 mm below where the floor stops the blade, about
// 2 N through the 500 N/m coupling) until the force is steady.
constexpr double kPressZ = 0.046;
void settle_pressing(World& w, int steps) {
  for (int i = 0; i < steps; ++i) w.step(at(Vec3(0, 0, std::max(0.07 - 1e-4 * i, kPressZ))));
}

TEST(WorldSafety, PoseJumpIsRejectedRecordedAndTheForceGoesToZero) {
  World w(small_box(false));
  settle_pressing(w, 1200);
  ASSERT_GT(w.last_frame().feedback_force_N.norm(), 0.5);
  std::vector<Event> ignore;
  w.drain_events(ignore);
  Frame f;
  for (int i = 0; i < 20; ++i) f = w.step(at(Vec3(0.05, 0, kPressZ)));  // a 5 cm teleport
  EXPECT_FALSE(f.input_valid);
  EXPECT_EQ(f.feedback_force_N, Vec3::Zero());
  EXPECT_LT(std::abs(f.instrument.position.x()), 1e-3);  // the instrument did not follow
  const auto rejected = kinds_of(w, EventKind::kInputRejected);
  ASSERT_EQ(rejected.size(), 1u);
  EXPECT_NEAR(rejected[0].value, 0.05, 1e-3);
  EXPECT_EQ(rejected[0].detail, "pose jump");
}

TEST(WorldSafety, LostInputHoldsTheInstrumentZeroesTheForceAndIsRecorded) {
  World w(small_box(false));
  settle_pressing(w, 1200);
  const double before = w.last_frame().feedback_force_N.norm();
  ASSERT_GT(before, 0.5);
  std::vector<Event> ignore;
  w.drain_events(ignore);
  DeviceSample lost = at(Vec3(0, 0, kPressZ));
  lost.stale = true;
  lost.silence_s = 0.06;
  Frame f;
  for (int i = 0; i < 20; ++i) f = w.step(lost);
  EXPECT_EQ(f.feedback_force_N, Vec3::Zero());
  EXPECT_FALSE(f.input_valid);
  const auto events = kinds_of(w, EventKind::kInputLost);
  ASSERT_EQ(events.size(), 1u);  // once per silence, not per step
  EXPECT_DOUBLE_EQ(events[0].value, 0.06);
  // Data returns: the force ramps in again instead of jumping back.
  f = w.step(at(Vec3(0, 0, kPressZ)));
  EXPECT_TRUE(f.input_valid);
  EXPECT_LT(f.feedback_force_N.norm(), 0.1 * before);
}

}  // namespace
}  // namespace acdr
