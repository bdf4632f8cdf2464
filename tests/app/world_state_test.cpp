// Tests of app/world_state: a capture holds the world's last frame, the instrument at its pose
// and every particle with its class, and a repeated capture reuses its buffers.
#include "app/world_state.hpp"

#include <gtest/gtest.h>

#include "engine/world/box_world.hpp"

namespace acdr {
namespace {

// The box scene with only the left half of the block in the removal region, so the right
// half counts as removed from the start.
WorldConfig half_removed_box() {
  BoxWorldOptions o;
  o.cavity_m = Vec3(16e-3, 12e-3, 8e-3);
  o.blade_m = Vec3(10e-3, 6e-3, 2e-3);
  o.shaft_length_m = 0.08;
  o.grip_height_m = 0.1;
  WorldConfig c = make_box_world(o);
  c.removal.max_m.x() = 0.0;
  return c;
}

TEST(WorldState, CapturesFrameInstrumentAndParticleClasses) {
  World world(half_removed_box());
  DeviceSample s;
  s.pose = world.config().instrument_start;
  for (int i = 0; i < 3; ++i) world.step(s);
  WorldState state;
  capture_world_state(world, state);

  EXPECT_EQ(state.frame.t_s, world.last_frame().t_s);
  EXPECT_EQ(state.instrument.size(), world.instrument_colliders().size());
  ASSERT_NE(world.nucleus(), nullptr);
  const std::size_t n = world.nucleus()->particle_count();
  ASSERT_EQ(state.positions.size(), n);
  ASSERT_EQ(state.particle_class.size(), n);
  std::size_t removed = 0, target = 0;
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_EQ(state.positions[i], world.nucleus()->positions()[i].cast<float>());
    const bool is_removed = state.particle_class[i] == ParticleClass::kRemoved;
    EXPECT_EQ(is_removed, world.is_removed(i)) << i;
    removed += is_removed;
    target += state.particle_class[i] == ParticleClass::kTarget;
  }
  // Both halves are there: material in place and material counted as removed.
  EXPECT_GT(removed, 0u);
  EXPECT_GT(target, 0u);
}

TEST(WorldState, ARepeatedCaptureReusesItsBuffers) {
  World world(half_removed_box());
  WorldState state;
  capture_world_state(world, state);
  const auto* positions = state.positions.data();
  const auto* classes = state.particle_class.data();
  const auto* instrument = state.instrument.data();
  DeviceSample s;
  s.pose = world.config().instrument_start;
  world.step(s);
  capture_world_state(world, state);
  EXPECT_EQ(state.positions.data(), positions);
  EXPECT_EQ(state.particle_class.data(), classes);
  EXPECT_EQ(state.instrument.data(), instrument);
}

TEST(WorldState, AWorldWithoutNucleusHasNoParticles) {
  WorldConfig c = half_removed_box();
  c.nucleus.enabled = false;
  World world(c);
  WorldState state;
  state.positions.resize(3);
  state.particle_class.resize(3);
  capture_world_state(world, state);
  EXPECT_TRUE(state.positions.empty());
  EXPECT_TRUE(state.particle_class.empty());
  EXPECT_FALSE(state.instrument.empty());
}

}  // namespace
}  // namespace acdr
