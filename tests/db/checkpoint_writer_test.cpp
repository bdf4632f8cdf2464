// Tests of db/checkpoint_writer.cpp: checkpoints made from a growing record concatenate into
// the record itself (frames, events, metrics of the record so far, duration), and a refused
// checkpoint warns once and reports that it was not saved.
#include "db/checkpoint_writer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "assessment/metrics.hpp"
#include "assessment/recording.hpp"
#include "tests/db/db_test_support.hpp"

namespace acdr {
namespace {

// A record of `frames` 1 kHz frames of a tip moving along a curve, with a zone warning.
AttemptRecording moving_tip(int frames) {
  AttemptRecording r;
  r.summary.dt_s = 1e-3;
  r.summary.particle_volume_m3 = 3.375e-9;
  r.summary.initial_target = 400;
  r.summary.yield_moment_Nm = 0.5;
  r.summary.warning_moment_Nm = 0.35;
  r.summary.device_max_force_N = 8.0;
  r.summary.zones.push_back(WorldSummary::Zone{"artery", 0.002, 1.0, true});
  for (int i = 0; i < frames; ++i) {
    Frame f;
    f.t_s = (i + 1) * 1e-3;
    f.tip_m = Vec3(0.01 * std::sin(f.t_s * 3.0), 0.002 * f.t_s, 0.004 - 0.01 * f.t_s);
    f.coupling_force_N = Vec3(0.1 * i, 0.0, -0.05 * i) * 1e-2;
    f.removed_target = i / 10;
    f.bending_moment_Nm = 1e-3 * i;
    f.zone_count = 1;
    f.zones[0].distance_m = static_cast<float>(0.005 - 1e-5 * i);
    f.zones[0].warning = f.zones[0].distance_m < 0.002f;
    r.frames.push_back(f);
  }
  return r;
}

// A record with one module and a running attempt on it.
class CheckpointWriterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    test::register_curriculum(db, 1);
    AttemptStart start;
    start.module_id = "m1";
    DbResult<std::int64_t> begun = begin_attempt(db, start);
    ASSERT_TRUE(begun.ok()) << begun.error().message;
    id = begun.value();
  }
  test::TempDir dir;
  Database db = test::open_or_fail(dir.file("record.sqlite"));
  std::int64_t id = 0;
};

TEST_F(CheckpointWriterTest, PiecesFromAGrowingRecordReadBackAsThatRecord) {

  const AttemptRecording whole = moving_tip(320);
  AttemptRecording growing;
  growing.summary = whole.summary;
  std::ostringstream err;
  CheckpointWriter writer(db, id, err);
  std::size_t first_frame = 0, first_event = 0, first_bone = 0;
  for (std::size_t end : {100u, 101u, 320u}) {
    growing.frames.assign(whole.frames.begin(), whole.frames.begin() + static_cast<long>(end));
    if (end == 320u)
      growing.events.push_back(Event{0.31, EventKind::kZoneWarning, 0.0019, "artery", 0});
    // A bone load sample every 10 frames (10 ms), as a scene with the bone model takes them.
    while (growing.bone_loads.size() < end / 10) {
      BoneLoadRecord& b = growing.bone_loads.emplace_back();
      b.t_s = 0.01 * static_cast<double>(growing.bone_loads.size());
      BoneLoadPoint p;
      p.point_m = Eigen::Vector3f(0.001f, -0.003f, static_cast<float>(b.t_s) * 0.01f);
      p.force_N = Eigen::Vector3f(0.0f, -0.5f * static_cast<float>(b.t_s), 0.1f);
      p.vertebra = 1;
      p.source = BoneLoadSource::kNucleus;
      b.points.assign(growing.bone_loads.size() % 3, p);
    }
    ASSERT_TRUE(writer.write(growing, first_frame, first_event, first_bone,
                             growing.frames.back().t_s));
    first_frame = growing.frames.size();
    first_event = growing.events.size();
    first_bone = growing.bone_loads.size();
  }
  EXPECT_EQ(writer.saved(), 3);
  EXPECT_TRUE(err.str().empty()) << err.str();
  ASSERT_TRUE(abort_attempt(db, id, "killed").ok());

  const AttemptRecord a = *load_attempt(db, id).value();
  ASSERT_TRUE(a.recording.has_value());
  EXPECT_FALSE(a.recording->complete);
  EXPECT_EQ(a.recording->frame_count, 320);
  std::string error;
  const auto decoded = decode_recording(a.recording->bytes, &error);
  ASSERT_TRUE(decoded) << error;
  ASSERT_EQ(decoded->frames.size(), 320u);
  for (std::size_t i = 0; i < 320; ++i) {
    ASSERT_EQ(decoded->frames[i].t_s, whole.frames[i].t_s) << i;
    ASSERT_EQ(decoded->frames[i].tip_m, whole.frames[i].tip_m) << i;
  }
  ASSERT_EQ(decoded->events.size(), 1u);
  EXPECT_EQ(decoded->events[0].kind, EventKind::kZoneWarning);
  // The bone's load samples came with the pieces, each once and in order: the stress history
  // of an attempt that never finished can be solved again.
  ASSERT_EQ(decoded->bone_loads.size(), 32u);
  for (std::size_t i = 0; i < 32; ++i) {
    ASSERT_EQ(decoded->bone_loads[i].t_s, growing.bone_loads[i].t_s) << i;
    ASSERT_EQ(decoded->bone_loads[i].points.size(), growing.bone_loads[i].points.size()) << i;
    for (std::size_t k = 0; k < growing.bone_loads[i].points.size(); ++k) {
      EXPECT_EQ(decoded->bone_loads[i].points[k].force_N, growing.bone_loads[i].points[k].force_N);
      EXPECT_EQ(decoded->bone_loads[i].points[k].vertebra, 1);
    }
  }
  // The stored metrics are those of the record so far, and of what reads back.
  EXPECT_EQ(a.metrics.values, compute_metrics(growing).values);
  EXPECT_EQ(a.metrics.values, compute_metrics(*decoded).values);
  EXPECT_EQ(a.duration_s, std::optional<double>(0.32));
  ASSERT_EQ(a.events.size(), 1u);
  EXPECT_EQ(a.events[0].kind, "zone_warning");
  EXPECT_EQ(a.events[0].zone, "artery");  // the zone's name from the summary
  EXPECT_EQ(a.events[0].zone_index, 0);
}

TEST_F(CheckpointWriterTest, ARefusedCheckpointIsNotSavedAndWarnsOnce) {
  ASSERT_TRUE(abort_attempt(db, id, "gone").ok());  // no longer running: the store refuses
  std::ostringstream err;
  CheckpointWriter writer(db, id, err);
  const AttemptRecording r = moving_tip(50);
  EXPECT_FALSE(writer.write(r, 0, 0, 0, 0.05));
  EXPECT_FALSE(writer.write(r, 0, 0, 0, 0.05));
  EXPECT_EQ(writer.saved(), 0);
  const std::string text = err.str();
  EXPECT_NE(text.find("warning: checkpoint not saved"), std::string::npos) << text;
  EXPECT_EQ(text.find("warning", 1), std::string::npos) << "warned twice: " << text;
}

}  // namespace
}  // namespace acdr
