// The attempt loop: ends when the input ends, honours the time limit, and gives bit-identical
// metrics for the same scenario and input (the determinism guarantee).
#include "app/attempt_runner.hpp"

#include <gtest/gtest.h>

#include "engine/devices/trajectory.hpp"
#include "engine/world/box_world.hpp"

namespace acdr {
namespace {

/// A small box scene (10 x 10 mm, 400 particles) with the prism.
ScenarioModel small_scenario() {
  ScenarioModel s;
  s.id = "small";
  BoxWorldOptions o;
  o.grip_height_m = 0.06;
  s.world = make_box_world(o);
  s.rubric.terms.push_back({"nucleus_removed_fraction", 0.1, 0.05, true, 1.0});
  s.rubric.gates.push_back({"overload_events", 0.0});
  return s;
}

/// Down into the material, across, and up again.
Trajectory dip() {
  std::vector<TrajectorySample> samples;
  auto add = [&](double t, double x, double z) {
    TrajectorySample s;
    s.t_s = t;
    s.pose.position = Vec3(x, 0, z);
    samples.push_back(s);
  };
  add(0.0, 0.0, 0.060);
  add(0.1, -2e-3, 0.0535);
  add(0.2, 2e-3, 0.0535);
  add(0.3, 2e-3, 0.062);
  return Trajectory(samples);
}

TEST(AttemptRunner, SameInputGivesIdenticalMetrics) {
  const ScenarioModel s = small_scenario();
  auto once = [&] {
    World world(s.world);
    TrajectoryReplay input(dip());
    return run_attempt(s, world, input);
  };
  const AttemptRun a = once(), b = once();
  EXPECT_EQ(a.end, AttemptEnd::kInputEnded);
  EXPECT_EQ(a.record.frames.size(), 300u);
  EXPECT_EQ(a.state_hash, b.state_hash);
  ASSERT_EQ(a.metrics.values.size(), b.metrics.values.size());
  for (std::size_t i = 0; i < a.metrics.values.size(); ++i)
    EXPECT_EQ(a.metrics.values[i], b.metrics.values[i]);  // bit-identical, names and values
  EXPECT_EQ(a.score.score, b.score.score);
  // The blade went through the material: it felt it.
  EXPECT_GT(*a.metrics.find("peak_instrument_force_N"), 1e-3);
}

TEST(AttemptRunner, StopsAtTheTimeLimit) {
  ScenarioModel s = small_scenario();
  s.time_limit_s = 0.05;
  World world(s.world);
  TrajectoryReplay input(dip());
  const AttemptRun run = run_attempt(s, world, input);
  EXPECT_EQ(run.end, AttemptEnd::kTimeLimit);
  EXPECT_EQ(run.record.frames.size(), 50u);
  ASSERT_FALSE(run.record.events.empty());
  EXPECT_EQ(run.record.events.back().kind, EventKind::kAttemptEnd);
}

TEST(AttemptRunner, InputSpellings) {
  std::string error;
  EXPECT_EQ(open_input("replay:", &error), nullptr);
  EXPECT_NE(error.find("needs a trajectory file"), std::string::npos);
  EXPECT_EQ(open_input("joystick:3", &error), nullptr);
  EXPECT_NE(error.find("unknown input"), std::string::npos);
  EXPECT_EQ(open_input("replay:/nonexistent/file.csv", &error), nullptr);
  EXPECT_NE(error.find("cannot open"), std::string::npos);
}

}  // namespace
}  // namespace acdr
