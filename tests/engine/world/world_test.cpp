// The assembled World: parts built only when declared, the virtual coupling, forces from the
// nucleus reaching the instrument, rigid contact with the box, and bit-for-bit determinism.
#include "engine/world/world.hpp"

#include "engine/world/box_world.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
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

// Step i of a press straight down into the block at 25 mm/s, held at 53.5 mm.
DeviceSample press(int i) { return at(Vec3(0, 0, std::max(0.07 - 2.5e-5 * i, 0.0535))); }

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

// Pipelined particle steps without an instrument: nothing moves but the particles, so the step
// launched at the end of a due step is the one that step's successor would have run, and the
// state, the counts and the iterations handed on match the steps run in place bit for bit.
TEST(World, PipelinedParticleStepsMatchTheStepsInPlaceWhenNothingElseMoves) {
  WorldConfig c = small_box();
  c.instrument.enabled = false;
  c.solver.nucleus_every = 3;
  WorldConfig p = c;
  p.solver.nucleus_pipelined = true;
  World in_place(c), pipelined(p);
  for (int i = 0; i < 300; ++i) {
    const Frame& f = in_place.step(DeviceSample{});
    const Frame& g = pipelined.step(DeviceSample{});
    ASSERT_EQ(f.solver_iterations, g.solver_iterations) << "step " << i;
    ASSERT_EQ(f.active_particles, g.active_particles) << "step " << i;
    ASSERT_EQ(f.removed_target, g.removed_target) << "step " << i;
  }
  // Read after a due step's launch: waits for the step in flight (one particle step on).
  World in_place_on(c);
  for (int i = 0; i < 303; ++i) in_place_on.step(DeviceSample{});
  EXPECT_EQ(pipelined.state_hash(), in_place_on.state_hash());
  // The particles settle by less than a skin: no neighbour rebuild, in place or made ahead
  // (one made ahead would give other rows, and other bits).
  EXPECT_EQ(pipelined.nucleus()->grid_builds(), 1u);
}

// Pipelined particle steps on their own thread give what the same steps run inline give (the
// thread only changes when the work is done): the same forces at every step and the same
// state, through a press into the material (25 mm/s: 75 um in the 3 ms predicted, within a
// quarter of the spacing, so the steps are launched ahead, and the press feels it against the
// same steps run in place).
TEST(World, PipelinedOnAThreadIsBitIdenticalToInline) {
  WorldConfig c = small_box();
  c.solver.nucleus_every = 4;
  WorldConfig pipelined = c;
  pipelined.solver.nucleus_pipelined = true;
  WorldConfig inline_config = pipelined;
  inline_config.solver.nucleus_thread = false;
  World threaded(pipelined), in_line(inline_config), in_place(c);
  double pressed = 0.0;
  int differs_from_in_place = 0;
  for (int i = 0; i < 900; ++i) {
    const Frame& f = threaded.step(press(i));
    const Frame& g = in_line.step(press(i));
    ASSERT_EQ(f.nucleus_force_N, g.nucleus_force_N) << "step " << i;
    ASSERT_EQ(f.instrument.position, g.instrument.position) << "step " << i;
    differs_from_in_place += f.nucleus_force_N != in_place.step(press(i)).nucleus_force_N;
    pressed = std::max(pressed, f.nucleus_force_N.z());
  }
  EXPECT_FALSE(threaded.failed());
  EXPECT_GT(pressed, 1e-3) << "the blade met the material";
  EXPECT_GT(differs_from_in_place, 0) << "no particle step was launched ahead";
  EXPECT_GT(threaded.nucleus()->rows_ahead_adopted(), 0u) << "no neighbour rebuild made ahead";
  EXPECT_EQ(threaded.nucleus()->rows_ahead_adopted(), in_line.nucleus()->rows_ahead_adopted());
  EXPECT_EQ(threaded.state_hash(), in_line.state_hash());
}

// Pipelined, what a reader between steps sees (the trainee view): the positions the last particle
// step handed on, not those of the step in flight, so it need not wait for it. Run inline, the
// step in flight has already run at its launch: the nucleus's own positions are one particle
// step ahead of what particle_positions() gives, which changes only at a hand-on, to what the
// step launched before produced (or, when none was launched, to what the due step ran).
TEST(World, PipelinedReadersBetweenStepsSeeThePositionsHandedOn) {
  WorldConfig c = small_box();
  c.solver.nucleus_every = 4;
  c.solver.nucleus_pipelined = true;
  c.solver.nucleus_thread = false;
  World w(c);
  auto copy = [](std::span<const Vec3> x) { return std::vector<Vec3>(x.begin(), x.end()); };
  std::vector<Vec3> shown = copy(w.particle_positions()), stepped = shown;
  int changes = 0, ahead = 0;
  for (int i = 0; i < 600; ++i) {
    w.step(press(i));
    const std::vector<Vec3> now = copy(w.particle_positions());
    if (now != shown) {
      // A step launched at an earlier step hands on what it produced then; with none in
      // flight (the prediction did not hold), the due step ran its own in place.
      if (stepped != shown) {
        ASSERT_EQ(now, stepped) << "step " << i << ": not what the launched step produced";
        ++changes;
      }
    }
    shown = now;
    stepped = copy(w.nucleus()->positions());
    ahead += stepped != shown;
  }
  ASSERT_FALSE(w.failed());
  EXPECT_GT(changes, 10) << "the particles moved at hand-ons";
  EXPECT_GT(ahead, 100) << "a step in flight was ahead of what readers see";
  EXPECT_TRUE(w.removed_at(Vec3(0, 0, 1.0)));
  EXPECT_EQ(w.particle_materials().size(), shown.size());
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

// The rongeur in the small box: 6 mm jaws at the end of the 50 mm shaft, 4 mm of nucleus.
WorldConfig rongeur_box() {
  WorldConfig c = small_box();
  c.instrument.shape = InstrumentShape::kRongeur;
  c.instrument.jaw_length_m = 6e-3;
  c.instrument.jaw_width_m = 3e-3;
  c.instrument.jaw_depth_m = 1e-3;
  return c;
}

DeviceSample grip_at(double z, double grip) {
  DeviceSample s = at(Vec3(0, 0, z));
  s.grip = grip;
  return s;
}

TEST(WorldGrasp, ClosedJawsCarryWhatIsBetweenThemAndOpeningLetsItGo) {
  // The grasp alone: opened above the box, the jaws would also shake the gel off (below).
  WorldConfig c = rongeur_box();
  c.instrument.jaw_shake_off = false;
  World w(c);
  const Nucleus& n = *w.nucleus();
  // Down with the jaws open until their tips are 0.8 mm above the floor, and rest.
  const double z0 = 0.07, z1 = 0.0568;
  for (int i = 0; i < 300; ++i) w.step(grip_at(z0 + (z1 - z0) * (i + 1) / 300.0, 0.0));
  for (int i = 0; i < 100; ++i) w.step(grip_at(z1, 0.0));
  EXPECT_TRUE(w.held_particles().empty());
  // Close: the jaws take 0.2 s (jaw_close_time_s) to follow the hand.
  w.step(grip_at(z1, 1.0));
  EXPECT_NEAR(w.jaw_closure(), 1e-3 / 0.2, 1e-12);
  for (int i = 0; i < 299; ++i) w.step(grip_at(z1, 1.0));
  EXPECT_DOUBLE_EQ(w.jaw_closure(), 1.0);
  const std::vector<std::int32_t> held(w.held_particles().begin(), w.held_particles().end());
  ASSERT_FALSE(held.empty());
  std::vector<std::uint8_t> is_held(n.particle_count(), 0);
  for (const std::int32_t i : held) {
    EXPECT_TRUE(n.is_kinematic(static_cast<std::size_t>(i)));
    is_held[static_cast<std::size_t>(i)] = 1;
  }
  // Every held particle lies between the jaws, in the body frame.
  const Pose grip = w.last_frame().instrument;
  for (const std::int32_t i : held) {
    const Vec3 local = grip.inverse_apply(n.positions()[static_cast<std::size_t>(i)]);
    EXPECT_TRUE(w.instrument()->between_jaws(local, 1.0)) << i;
  }
  // Lift 18 mm: the bite comes out of the box with the jaws, the rest stays in it.
  const double z2 = 0.075;
  for (int i = 0; i < 400; ++i) w.step(grip_at(z1 + (z2 - z1) * std::min(1.0, (i + 1) / 300.0), 1.0));
  ASSERT_FALSE(w.failed());
  const Pose lifted = w.last_frame().instrument;
  std::size_t free_out = 0, free_total = 0;
  for (std::size_t i = 0; i < n.particle_count(); ++i) {
    const Vec3& x = n.positions()[i];
    if (is_held[i]) {
      EXPECT_GT(x.z(), 0.012) << "held particle " << i << " left behind";
      // It kept its place on the jaws.
      EXPECT_TRUE(w.instrument()->between_jaws(lifted.inverse_apply(x), 1.0)) << i;
    } else {
      ++free_total;
      if (x.z() > 0.008) ++free_out;
    }
  }
  EXPECT_LT(free_out, free_total / 20) << "the free gel came out with the bite";
  EXPECT_GE(w.last_frame().removed_target, static_cast<std::int32_t>(held.size()));
  // The hand holds the bite's weight: the nucleus's force on the instrument points down by
  // about the held mass times g (the lift has stopped, the torn bonds no longer pull).
  double held_mass = 0.0;
  for (const std::int32_t i : held) held_mass += n.masses()[static_cast<std::size_t>(i)];
  EXPECT_NEAR(w.last_frame().nucleus_force_N.z(), -held_mass * 9.80665, 0.2 * held_mass * 9.80665);
  // Open while the hand rises at 20 mm/s: at half closure the jaws let go, and the particles
  // are free again where they were, moving as the jaws moved.
  std::vector<Vec3> before;
  double z = z2;
  bool released = false;
  for (int i = 0; i < 300 && !released; ++i) {
    before.clear();
    for (const std::int32_t k : held) before.push_back(n.positions()[static_cast<std::size_t>(k)]);
    z += 2e-5;
    w.step(grip_at(z, 0.0));
    released = w.held_particles().empty();
  }
  ASSERT_TRUE(released);
  EXPECT_NEAR(w.jaw_closure(), 0.5, 0.006);
  double vz = 0.0, jump = 0.0;
  for (std::size_t k = 0; k < held.size(); ++k) {
    const auto i = static_cast<std::size_t>(held[k]);
    EXPECT_FALSE(n.is_kinematic(i));
    vz += n.velocities()[i].z();
    jump = std::max(jump, (n.positions()[i] - before[k]).norm());
  }
  EXPECT_NEAR(vz / static_cast<double>(held.size()), 0.02, 0.006);
  EXPECT_LT(jump, 1e-4);
  // They step with the free gel from then on.
  for (int i = 0; i < 100; ++i) w.step(grip_at(z, 0.0));
  for (const std::int32_t k : held) EXPECT_FALSE(n.is_kinematic(static_cast<std::size_t>(k)));
  ASSERT_FALSE(w.failed());
}

TEST(WorldGrasp, AngledJawsHoldTheBiteAlongTheirBentAxis) {
  // Jaws bent 30 degrees toward +x, plunged open into the box 1.5 mm left of its middle (so
  // the far jaw, 55 degrees off the shaft, stays clear of the wall) and closed there.
  WorldConfig c = rongeur_box();
  c.instrument.jaw_shake_off = false;
  const double bend = 30.0 * std::numbers::pi / 180.0;
  c.instrument.jaw_angle_rad = bend;
  World w(c);
  const Nucleus& n = *w.nucleus();
  auto grip = [](double z, double closure) {
    DeviceSample s = at(Vec3(-1.5e-3, 0, z));
    s.grip = closure;
    return s;
  };
  const double z0 = 0.07, z1 = 0.0568;
  for (int i = 0; i < 300; ++i) w.step(grip(z0 + (z1 - z0) * (i + 1) / 300.0, 0.0));
  for (int i = 0; i < 100; ++i) w.step(grip(z1, 0.0));
  for (int i = 0; i < 300; ++i) w.step(grip(z1, 1.0));
  ASSERT_FALSE(w.failed());
  const std::vector<std::int32_t> held(w.held_particles().begin(), w.held_particles().end());
  ASSERT_GT(held.size(), 5u);
  // Every held particle lies between the bent jaws, and the bite along their axis: its middle
  // off the shaft's axis toward +x, within the 2 mm between the closed jaws' inner faces.
  const Pose pose = w.last_frame().instrument;
  const InstrumentGeometry& g = *w.instrument();
  const Vec3 axis(std::sin(bend), 0.0, -std::cos(bend));
  const Vec3 across(std::cos(bend), 0.0, std::sin(bend));
  Vec3 mean = Vec3::Zero();
  for (const std::int32_t i : held) {
    const Vec3 local = pose.inverse_apply(n.positions()[static_cast<std::size_t>(i)]);
    EXPECT_TRUE(g.between_jaws(local, 1.0)) << i;
    EXPECT_LE(std::abs((local - g.hinge()).dot(across)), 1.0e-3 + 1e-9) << i;
    mean += local / static_cast<double>(held.size());
  }
  EXPECT_GT(mean.x(), 0.5e-3);
  EXPECT_GT((mean - g.hinge()).dot(axis), 0.0);
}

// Bite, lift the jaws 25 mm above the box (out of the removal region) and open them there;
// then hold 1 s. Returns how many of the bitten particles still hang above the box's rim.
std::size_t bite_left_on_open_jaws(bool shake_off) {
  WorldConfig c = rongeur_box();
  c.instrument.jaw_shake_off = shake_off;
  World w(c);
  const Nucleus& n = *w.nucleus();
  const double z0 = 0.07, z1 = 0.0568, z2 = 0.075;
  for (int i = 0; i < 300; ++i) w.step(grip_at(z0 + (z1 - z0) * (i + 1) / 300.0, 0.0));
  for (int i = 0; i < 300; ++i) w.step(grip_at(z1, 1.0));
  const std::vector<std::int32_t> held(w.held_particles().begin(), w.held_particles().end());
  EXPECT_GT(held.size(), 10u);
  for (int i = 0; i < 400; ++i) w.step(grip_at(z1 + (z2 - z1) * std::min(1.0, (i + 1) / 300.0), 1.0));
  for (int i = 0; i < 1300; ++i) w.step(grip_at(z2, 0.0));
  EXPECT_FALSE(w.failed());
  std::size_t left = 0;
  for (const std::int32_t i : held) left += n.positions()[static_cast<std::size_t>(i)].z() > 0.012;
  return left;
}

TEST(WorldGrasp, OpenJawsOutsideTheDiscShedWhatLiesOnThem) {
  // Without the shake the gel clings to the plates (a 300 Pa s film creeps off at some
  // 30 um/s); shaken off, what lay between the jaws falls into the box below.
  const std::size_t clinging = bite_left_on_open_jaws(false);
  const std::size_t shaken = bite_left_on_open_jaws(true);
  EXPECT_GT(clinging, 5u);
  EXPECT_LT(shaken, clinging / 4) << clinging << " cling without the shake";
}

// Whether every instrument collider lets the gel slide (the shake-off).
bool all_slip(const World& w) {
  const auto& colliders = w.instrument_colliders();
  return !colliders.empty() && std::all_of(colliders.begin(), colliders.end(),
                                           [](const Collider& c) { return c.slip; });
}

TEST(WorldGrasp, JawsShakeTheBiteOffFromTheirFirstOpeningOutsideTheDisc) {
  // Held rigidly until the jaws let go (half closure), the bite has gel clinging to the parting
  // plates sheared between them; in module 03's 3000 Pa s gel that pulled up to 10-20 N on the
  // jaws opened in the air. Outside the disc the film slides from the first opening step;
  // inside it, opening keeps the no-slip coupling until the jaws are open.
  WorldConfig c = rongeur_box();
  World w(c);
  const double z0 = 0.07, z1 = 0.0568, z2 = 0.075;
  for (int i = 0; i < 300; ++i) w.step(grip_at(z0 + (z1 - z0) * (i + 1) / 300.0, 0.0));
  for (int i = 0; i < 300; ++i) w.step(grip_at(z1, 1.0));
  ASSERT_FALSE(w.held_particles().empty());
  // Opening in the box: no slip while the jaws still hold the bite.
  for (int i = 0; i < 20; ++i) w.step(grip_at(z1, 0.0));
  EXPECT_GT(w.jaw_closure(), 0.8);
  EXPECT_FALSE(w.held_particles().empty());
  EXPECT_FALSE(all_slip(w));
  // Closed again and lifted 25 mm out of the removal region: no slip while closed.
  for (int i = 0; i < 100; ++i) w.step(grip_at(z1, 1.0));
  for (int i = 0; i < 400; ++i) w.step(grip_at(z1 + (z2 - z1) * std::min(1.0, (i + 1) / 300.0), 1.0));
  ASSERT_FALSE(w.held_particles().empty());
  EXPECT_FALSE(all_slip(w));
  // Opening there: the film slides from the first steps, while the bite is still held.
  for (int i = 0; i < 4; ++i) w.step(grip_at(z2, 0.0));
  EXPECT_GT(w.jaw_closure(), 0.9);
  EXPECT_FALSE(w.held_particles().empty());
  EXPECT_TRUE(all_slip(w));
  ASSERT_FALSE(w.failed());
}

// The small box's blade and a rongeur on one tray.
WorldConfig tray_box() {
  WorldConfig c = small_box();
  InstrumentConfig blade = c.instrument;
  blade.name = "blade";
  InstrumentConfig rongeur = rongeur_box().instrument;
  rongeur.name = "rongeur";
  c.instruments = {blade, rongeur};
  return c;
}

DeviceSample asking(double z, int instrument, double grip = 0.0) {
  DeviceSample s = grip_at(z, grip);
  s.instrument = instrument;
  return s;
}

TEST(WorldExchange, ATrayNeverExchangedStepsAsItsFirstInstrumentAlone) {
  World alone(small_box()), tray(tray_box());
  for (int i = 0; i < 600; ++i) {
    const double z = std::max(0.07 - 2.5e-5 * i, 0.056);
    alone.step(at(Vec3(0, 0, z)));
    tray.step(asking(z, 0));
  }
  EXPECT_EQ(alone.state_hash(), tray.state_hash());
  EXPECT_EQ(alone.last_frame().nucleus_force_N, tray.last_frame().nucleus_force_N);
  EXPECT_EQ(tray.instrument_index(), 0);
}

TEST(WorldExchange, TheHandTakesTheOtherInstrumentOnlyOutsideTheDiscAndEmpty) {
  World w(tray_box());
  std::vector<Event> events;
  // The blade down into the nucleus (its tip 1 mm deep in the gel), then the hand asks for the
  // rongeur: no exchange inside the removal region.
  for (int i = 0; i < 600; ++i) w.step(asking(std::max(0.07 - 3e-5 * i, 0.053), 0));
  for (int i = 0; i < 100; ++i) w.step(asking(0.053, 1));
  EXPECT_EQ(w.instrument_index(), 0);
  EXPECT_FALSE(w.instrument()->config().has_jaws());
  // Out again: the exchange happens once the blade has left the region (its top at 8 mm).
  double z = 0.053;
  Pose before = w.last_frame().instrument;
  double jump = 0.0;
  for (int i = 0; i < 700 && w.instrument_index() == 0; ++i) {
    z = std::min(0.07, z + 3e-5);
    before = w.last_frame().instrument;
    w.step(asking(z, 1));
    jump = (w.last_frame().instrument.position - before.position).norm();
  }
  ASSERT_EQ(w.instrument_index(), 1);
  EXPECT_TRUE(w.instrument()->config().has_jaws());
  EXPECT_LT(jump, 1e-4);  // the hand holds the new one where it held the old one
  const Vec3 tip = w.last_frame().instrument.apply(Vec3(0, 0, -0.05));
  EXPECT_GT(tip.z(), 0.008);  // above the region
  w.drain_events(events);
  std::vector<Event> exchanges;
  for (const Event& e : events)
    if (e.kind == EventKind::kInstrumentExchange) exchanges.push_back(e);
  ASSERT_EQ(exchanges.size(), 1u);
  EXPECT_EQ(exchanges[0].value, 1.0);
  EXPECT_EQ(exchanges[0].detail, "rongeur");
  EXPECT_STREQ(event_kind_name(EventKind::kInstrumentExchange), "instrument_exchange");
  // The rongeur bites as a rongeur.
  const double z1 = 0.0568;
  for (int i = 0; i < 300; ++i) w.step(asking(0.07 + (z1 - 0.07) * (i + 1) / 300.0, 1));
  for (int i = 0; i < 300; ++i) w.step(asking(z1, 1, 1.0));
  ASSERT_FALSE(w.held_particles().empty());
  // Out with the bite, asking for the blade: not while the jaws hold something.
  for (int i = 0; i < 400; ++i) w.step(asking(std::min(0.075, z1 + 5e-5 * i), 0, 1.0));
  EXPECT_EQ(w.instrument_index(), 1);
  // Opened, they let go; then the blade comes back.
  for (int i = 0; i < 300; ++i) w.step(asking(0.075, 0, 0.0));
  EXPECT_TRUE(w.held_particles().empty());
  EXPECT_EQ(w.instrument_index(), 0);
  EXPECT_FALSE(w.instrument()->config().has_jaws());
  for (int i = 0; i < 300; ++i) w.step(asking(0.07, 2));  // 2 modulo the tray's 2: the blade
  EXPECT_EQ(w.instrument_index(), 0);
  EXPECT_FALSE(w.failed());
}

TEST(WorldGrasp, OtherInstrumentsIgnoreTheGrip) {
  World a(small_box()), b(small_box());
  for (int i = 0; i < 200; ++i) {
    DeviceSample s = at(Vec3(0, 0, 0.07 - 1e-4 * i));
    a.step(s);
    s.grip = 1.0;
    b.step(s);
  }
  EXPECT_EQ(a.state_hash(), b.state_hash());
  EXPECT_DOUBLE_EQ(b.jaw_closure(), 0.0);
}

}  // namespace
}  // namespace acdr
