// The bone metrics of an attempt: computed beside the run on the bone's worker thread, stored
// with the recording's load samples, and computed again from the decoded recording, they are
// the same bit for bit; a scenario without the bone model gets none.
#include "app/bone_metrics_replay.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "app/attempt_runner.hpp"
#include "assessment/metric_catalog.hpp"
#include "assessment/recording.hpp"
#include "engine/devices/trajectory.hpp"
#include "tests/engine/anatomy/coarse_segment_scene.hpp"

namespace acdr {
namespace {

class BoneReplay : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = (std::filesystem::temp_directory_path() /
            ("acdr_bone_replay_" + std::to_string(::getpid())))
               .string();
    std::filesystem::remove_all(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  /// The coarse segment with the bone modelled at 3 mm elements, cached in the test's folder.
  ScenarioModel scenario() const {
    ScenarioModel s;
    s.path = dir_ + "/segment.json";
    s.hash = "test";
    s.id = "bone-replay";
    s.world = test::coarse_segment_world(dir_);
    s.bone.enabled = true;
    s.bone.fem.meshing.size_m = 3.0e-3;
    s.world.anatomy.bone_load_period_s = s.bone.sample_period_s;
    s.world.anatomy.bone_load_cell_m = s.bone.nucleus_cell_m;
    return s;
  }
  std::string dir_;
};

TEST_F(BoneReplay, MetricsFromTheStoredRecordingEqualTheLiveOnes) {
  const ScenarioModel s = scenario();
  // Down onto C5's endplate in 0.15 s, held, then back: 0.4 s, 40 load samples.
  const Pose start = s.world.instrument_start;
  const Pose push = test::coarse_segment_push(s.world);
  Trajectory path({{0.0, start}, {0.15, push}, {0.3, push}, {0.4, start}});
  TrajectoryReplay device(path);
  World world(s.world);
  const AttemptRun run = run_attempt(s, world, device);
  ASSERT_TRUE(run.bone_modelled);
  ASSERT_EQ(run.bone_error, "");
  EXPECT_GE(run.record.bone_loads.size(), 39u);
  EXPECT_EQ(run.bone_stats.samples, static_cast<std::int64_t>(run.record.bone_loads.size()));
  EXPECT_GT(run.bone_stats.solves, 0);
  for (const MetricInfo& m : bone_metric_catalog()) ASSERT_NE(run.metrics.find(m.name), nullptr) << m.name;
  EXPECT_GT(*run.metrics.find("endplate_c5_peak_stress_MPa"), 0.0);
  EXPECT_GT(*run.metrics.find("bone_peak_load_N"), 0.0);

  // Stored and read back, then solved again from the recorded loads.
  std::string error;
  const auto decoded = decode_recording(encode_recording(run.record), &error);
  ASSERT_TRUE(decoded) << error;
  Metrics again;
  BoneMetricsReplay replay;
  ASSERT_TRUE(replay.add_metrics(s, *decoded, again, &error)) << error;
  for (const MetricInfo& m : bone_metric_catalog()) {
    ASSERT_NE(again.find(m.name), nullptr) << m.name;
    EXPECT_EQ(*again.find(m.name), *run.metrics.find(m.name)) << m.name;
  }

  // Without the bone model: no samples are taken and no bone metric is made.
  ScenarioModel off = scenario();
  off.bone.enabled = false;
  off.world.anatomy.bone_load_period_s = 0.0;
  TrajectoryReplay device2(path);
  World world2(off.world);
  const AttemptRun plain = run_attempt(off, world2, device2);
  EXPECT_FALSE(plain.bone_modelled);
  EXPECT_TRUE(plain.record.bone_loads.empty());
  EXPECT_EQ(plain.metrics.find("endplate_peak_stress_MPa"), nullptr);
  // ... and the physics is the same as with it.
  EXPECT_EQ(plain.state_hash, run.state_hash);
  Metrics none;
  ASSERT_TRUE(replay.add_metrics(off, *decoded, none, &error));
  EXPECT_TRUE(none.values.empty());
}

}  // namespace
}  // namespace acdr
