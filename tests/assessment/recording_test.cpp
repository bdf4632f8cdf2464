// Recordings survive a round trip bit for bit, and damaged ones are refused.
#include "assessment/recording.hpp"

#include <gtest/gtest.h>

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
  EXPECT_NE(error.find("trailing"), std::string::npos);
  EXPECT_FALSE(decode_recording({}, &error));
}

}  // namespace
}  // namespace acdr
