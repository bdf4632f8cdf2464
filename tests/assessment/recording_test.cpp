// Recordings survive a round trip bit for bit, and damaged ones are refused.
#include "assessment/recording.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <span>

#include "assessment/metrics.hpp"

namespace acdr {
namespace {

AttemptRecording sample_record() {
  AttemptRecording r;
  r.summary.dt_s = 1e-3;
  r.summary.particle_volume_m3 = 1e-9;
  r.summary.initial_target = 4800;
  r.summary.yield_moment_Nm = 0.39;
  for (int i = 0; i < 300; ++i) {
    Frame f;
    f.t_s = i * 1e-3;
    f.tip_m = Vec3(std::sin(i * 0.1), 0.1 / (i + 1), 1e-3 * i);
    f.instrument.orientation = Quat(Eigen::AngleAxisd(i * 0.01, Vec3::UnitY()));
    f.nucleus_force_N = Vec3(0.1, 0.2, 0.3 * i);
    f.bending_moment_Nm = 1e-3 * i;
    f.removed_target = i;
    f.input_valid = i % 7 != 0;
    r.frames.push_back(f);
  }
  r.events.push_back({0.05, EventKind::kOverloadWarning, 0.2, "shaft moment above warning"});
  r.events.push_back({0.07, EventKind::kInputRejected, 0.05, ""});
  return r;
}

TEST(Recording, RoundTripReproducesMetricsExactly) {
  const AttemptRecording r = sample_record();
  const auto bytes = encode_recording(r);
  std::string error;
  const auto back = decode_recording(bytes, &error);
  ASSERT_TRUE(back) << error;
  ASSERT_EQ(back->frames.size(), r.frames.size());
  ASSERT_EQ(back->events.size(), 2u);
  EXPECT_EQ(back->events[0].detail, "shaft moment above warning");
  EXPECT_EQ(back->frames[7].input_valid, false);
  const Metrics a = compute_metrics(r), b = compute_metrics(*back);
  ASSERT_EQ(a.values.size(), b.values.size());
  for (std::size_t i = 0; i < a.values.size(); ++i)
    EXPECT_EQ(a.values[i].second, b.values[i].second) << a.values[i].first;  // bit-identical
}

TEST(Recording, DamagedDataIsRefused) {
  auto bytes = encode_recording(sample_record());
  std::string error;
  auto cut = bytes;
  cut.resize(cut.size() / 2);
  EXPECT_FALSE(decode_recording(cut, &error));
  EXPECT_FALSE(error.empty());
  auto foreign = bytes;
  foreign[0] = 'X';  // not our magic
  EXPECT_FALSE(decode_recording(foreign, &error));
  auto longer = bytes;
  longer.push_back(0);
  EXPECT_FALSE(decode_recording(longer, &error));
  // v2 reads blocks to the end: a stray byte is a block cut short.
  EXPECT_NE(error.find("truncated block"), std::string::npos) << error;
  auto v1_longer = encode_recording_v1(sample_record());
  v1_longer.push_back(0);
  EXPECT_FALSE(decode_recording(v1_longer, &error));
  EXPECT_NE(error.find("trailing"), std::string::npos) << error;
  EXPECT_FALSE(decode_recording({}, &error));
}

AttemptRecording zoned_record() {
  AttemptRecording r = sample_record();
  r.summary.zones = {{"vertebral_artery_left", 1.5e-3, 2.0, true}, {"Endplate C4", 1e-3, 5.0, false}};
  for (std::size_t i = 0; i < r.frames.size(); ++i) {
    Frame& f = r.frames[i];
    f.zone_count = 2;
    f.zones[0] = {static_cast<float>(3e-3 - 1e-5 * i), 0.01f * i, i > 290, i > 150};
    f.zones[1] = {static_cast<float>(1e-3 * std::cos(0.05 * i)), 0.5f, false, i % 3 == 0};
  }
  Event e{0.151, EventKind::kZoneWarning, 1.49e-3, "vertebral_artery_left"};
  e.zone = 0;
  r.events.push_back(e);
  e = {0.291, EventKind::kNeverEvent, -1e-5, "vertebral_artery_left"};
  e.zone = 0;
  r.events.push_back(e);
  return r;
}

void expect_same_metrics(const AttemptRecording& a, const AttemptRecording& b) {
  const Metrics ma = compute_metrics(a), mb = compute_metrics(b);
  ASSERT_EQ(ma.values.size(), mb.values.size());
  for (std::size_t i = 0; i < ma.values.size(); ++i) {
    EXPECT_EQ(ma.values[i].first, mb.values[i].first);
    EXPECT_EQ(ma.values[i].second, mb.values[i].second) << ma.values[i].first;  // bit-identical
  }
}

TEST(Recording, V2KeepsZonesAndEventZonesForRescoring) {
  const AttemptRecording r = zoned_record();
  const auto bytes = encode_recording(r);
  std::string error;
  const auto back = decode_recording(bytes, &error);
  ASSERT_TRUE(back) << error;
  ASSERT_EQ(back->summary.zones.size(), 2u);
  EXPECT_EQ(back->summary.zones[1].name, "Endplate C4");
  EXPECT_EQ(back->summary.zones[0].warning_distance_m, 1.5e-3);
  EXPECT_EQ(back->summary.zones[0].force_limit_N, 2.0);
  EXPECT_TRUE(back->summary.zones[0].never_event);
  EXPECT_FALSE(back->summary.zones[1].never_event);
  ASSERT_EQ(back->events.size(), 4u);
  EXPECT_EQ(back->events[3].kind, EventKind::kNeverEvent);
  EXPECT_EQ(back->events[3].zone, 0);
  EXPECT_EQ(back->events[0].zone, -1);
  for (std::size_t i = 0; i < r.frames.size(); ++i) {
    const Frame &x = r.frames[i], &y = back->frames[i];
    ASSERT_EQ(x.t_s, y.t_s);
    ASSERT_EQ(x.tip_m, y.tip_m);
    ASSERT_EQ(x.instrument.orientation.coeffs(), y.instrument.orientation.coeffs());
    ASSERT_EQ(x.input_valid, y.input_valid);
    ASSERT_EQ(x.zone_count, y.zone_count);
    for (int k = 0; k < 2; ++k) {
      ASSERT_EQ(x.zones[k].distance_m, y.zones[k].distance_m);
      ASSERT_EQ(x.zones[k].force_N, y.zones[k].force_N);
      ASSERT_EQ(x.zones[k].inside, y.zones[k].inside);
      ASSERT_EQ(x.zones[k].warning, y.zones[k].warning);
    }
  }
  expect_same_metrics(r, *back);
  EXPECT_NE(compute_metrics(*back).find("zone.endplate_c4.dwell_s"), nullptr);
}

TEST(Recording, PiecesWrittenAtCheckpointsConcatenateToTheSameRecording) {
  const AttemptRecording r = zoned_record();
  std::vector<std::uint8_t> bytes = encode_recording_header(r.summary);
  // Checkpoints of 70 frames with the events so far, as a running attempt writes them.
  std::size_t events_done = 0;
  std::vector<std::size_t> boundaries;
  for (std::size_t i = 0; i < r.frames.size(); i += 70) {
    const std::size_t n = std::min<std::size_t>(70, r.frames.size() - i);
    append_frame_block(std::span(r.frames).subspan(i, n), bytes);
    std::size_t upto = events_done;
    while (upto < r.events.size() && r.events[upto].t_s <= r.frames[i + n - 1].t_s) ++upto;
    append_event_block(std::span(r.events).subspan(events_done, upto - events_done), bytes);
    events_done = upto;
    boundaries.push_back(bytes.size());
  }
  append_event_block(std::span(r.events).subspan(events_done), bytes);
  std::string error;
  const auto back = decode_recording(bytes, &error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->frames.size(), r.frames.size());
  EXPECT_EQ(back->events.size(), r.events.size());
  expect_same_metrics(r, *back);

  // A prefix ending on a checkpoint decodes to the frames so far; one cut inside a block does
  // not decode at all.
  std::vector<std::uint8_t> prefix(bytes.begin(), bytes.begin() + boundaries[1]);
  const auto partial = decode_recording(prefix, &error);
  ASSERT_TRUE(partial) << error;
  EXPECT_EQ(partial->frames.size(), 140u);
  prefix.resize(prefix.size() - 3);
  EXPECT_FALSE(decode_recording(prefix, &error));
  EXPECT_NE(error.find("truncated"), std::string::npos) << error;
}

TEST(Recording, OldV1RecordingsAreStillRead) {
  const AttemptRecording r = sample_record();
  const auto v1 = encode_recording_v1(r);
  EXPECT_EQ(std::string(v1.begin(), v1.begin() + 8), "ACDRREC1");
  std::string error;
  const auto back = decode_recording(v1, &error);
  ASSERT_TRUE(back) << error;
  EXPECT_TRUE(back->summary.zones.empty());
  expect_same_metrics(r, *back);
  EXPECT_TRUE(is_known_recording_format("acdr-frames-v1"));
  EXPECT_TRUE(is_known_recording_format(kRecordingFormat));
  EXPECT_FALSE(is_known_recording_format("acdr-frames-v3"));
}

TEST(Recording, ManyBlocksAndSpecialValuesSurvive) {
  AttemptRecording r = sample_record();
  r.frames.resize(2 * kRecordingBlockFrames + 5, r.frames.back());
  r.frames[10].bending_moment_Nm = std::numeric_limits<double>::quiet_NaN();
  r.frames[11].bending_moment_Nm = -std::numeric_limits<double>::infinity();
  r.frames[12].bending_moment_Nm = -0.0;
  r.frames[13].removed_target = std::numeric_limits<std::int32_t>::min();
  r.frames[14].removed_target = std::numeric_limits<std::int32_t>::max();
  std::string error;
  const auto back = decode_recording(encode_recording(r), &error);
  ASSERT_TRUE(back) << error;
  ASSERT_EQ(back->frames.size(), r.frames.size());
  EXPECT_TRUE(std::isnan(back->frames[10].bending_moment_Nm));
  EXPECT_EQ(back->frames[11].bending_moment_Nm, -std::numeric_limits<double>::infinity());
  EXPECT_TRUE(std::signbit(back->frames[12].bending_moment_Nm));
  EXPECT_EQ(back->frames[13].removed_target, std::numeric_limits<std::int32_t>::min());
  EXPECT_EQ(back->frames[14].removed_target, std::numeric_limits<std::int32_t>::max());
  EXPECT_EQ(back->frames.back().tip_m, r.frames.back().tip_m);
}

}  // namespace
}  // namespace acdr

namespace acdr {
namespace {

// The bone's load samples come back with the same bits (the re-computed stresses depend on
// it), and a damaged bone block is refused with its reason.
TEST(Recording, BoneLoadSamplesSurviveBitForBit) {
  AttemptRecording r = sample_record();
  for (int k = 0; k < 30; ++k) {
    BoneLoadRecord& s = r.bone_loads.emplace_back();
    s.t_s = 0.01 * (k + 1);
    for (int i = 0; i < k % 5; ++i) {
      BoneLoadPoint p;
      p.point_m = Eigen::Vector3f(1e-3f * i, -2.9e-3f + 1e-5f * k, 3e-3f / (i + 1));
      p.force_N = Eigen::Vector3f(0.1f * i, -1.0f / (k + 1), 1e-7f);
      p.radius_m = i % 2 ? 1e-3f : 0.0f;
      p.vertebra = static_cast<std::uint8_t>(i % 2);
      p.source = i % 2 ? BoneLoadSource::kNucleus : BoneLoadSource::kInstrument;
      s.points.push_back(p);
    }
  }
  const auto bytes = encode_recording(r);
  std::string error;
  const auto back = decode_recording(bytes, &error);
  ASSERT_TRUE(back) << error;
  ASSERT_EQ(back->bone_loads.size(), r.bone_loads.size());
  for (std::size_t k = 0; k < r.bone_loads.size(); ++k) {
    const BoneLoadRecord& a = r.bone_loads[k];
    const BoneLoadRecord& b = back->bone_loads[k];
    EXPECT_EQ(a.t_s, b.t_s);
    ASSERT_EQ(a.points.size(), b.points.size());
    for (std::size_t i = 0; i < a.points.size(); ++i) {
      EXPECT_EQ(a.points[i].point_m, b.points[i].point_m);
      EXPECT_EQ(a.points[i].force_N, b.points[i].force_N);
      EXPECT_EQ(a.points[i].radius_m, b.points[i].radius_m);
      EXPECT_EQ(a.points[i].vertebra, b.points[i].vertebra);
      EXPECT_EQ(a.points[i].source, b.points[i].source);
    }
  }
  EXPECT_EQ(back->frames.size(), r.frames.size());
  // A vertebra other than C4 or C5 is refused. The bone block ends the recording; its last
  // load is 30 bytes (point, force, radius as f32, vertebra and source bytes).
  auto bad = bytes;
  const std::size_t last_load = bad.size() - 4 * (3 + 3 + 1) - 2;
  bad[last_load + 28] = 7;  // its vertebra byte
  EXPECT_FALSE(decode_recording(bad, &error));
  EXPECT_NE(error.find("vertebra"), std::string::npos) << error;
  // A recording without bone samples has an empty list (old recordings, box modules).
  const auto plain = decode_recording(encode_recording(sample_record()), &error);
  ASSERT_TRUE(plain);
  EXPECT_TRUE(plain->bone_loads.empty());
}

}  // namespace
}  // namespace acdr

namespace acdr {
namespace {

TEST(Recording, RemovedMaterialSurvivesAndGivesTheLumpMetrics) {
  AttemptRecording r = sample_record();  // particle volume 1 mm^3: spacing 1 mm
  std::vector<Eigen::Vector3f> removed;
  for (int i = 0; i < 12; ++i) removed.emplace_back(1e-3f * i, 0.0f, 0.0f);  // a row of 12
  removed.emplace_back(0.5f, 0.5f, 0.5f);                                    // a stray one
  r.removed_positions = removed;
  std::string error;
  const auto back = decode_recording(encode_recording(r), &error);
  ASSERT_TRUE(back) << error;
  ASSERT_TRUE(back->removed_positions);
  EXPECT_EQ(*back->removed_positions, removed);
  const Metrics m = compute_metrics(*back);
  ASSERT_NE(m.find("removed_lump_fraction"), nullptr);
  EXPECT_DOUBLE_EQ(*m.find("removed_lump_fraction"), 12.0 / 13.0);
  EXPECT_EQ(*m.find("removed_clusters"), 2.0);
  EXPECT_EQ(*m.find("removed_lumps"), 1.0);
  EXPECT_EQ(*m.find("removed_largest_cluster"), 12.0);
  // Nothing removed is recorded as such (a block of none), and differs from not recorded.
  r.removed_positions.emplace();
  const auto none = decode_recording(encode_recording(r), &error);
  ASSERT_TRUE(none && none->removed_positions);
  EXPECT_TRUE(none->removed_positions->empty());
  EXPECT_EQ(*compute_metrics(*none).find("removed_lump_fraction"), 0.0);
  const auto old = decode_recording(encode_recording(sample_record()), &error);
  ASSERT_TRUE(old);
  EXPECT_FALSE(old->removed_positions);
  EXPECT_EQ(compute_metrics(*old).find("removed_lump_fraction"), nullptr);
  // A count larger than the block holds is refused.
  auto bad = encode_recording(r);
  bad[bad.size() - 4] = 9;
  EXPECT_FALSE(decode_recording(bad, &error));
}

}  // namespace
}  // namespace acdr
