// Metrics over a synthetic record with known answers.
#include "assessment/metrics.hpp"

#include <gtest/gtest.h>

namespace acdr {
namespace {

AttemptRecording synthetic() {
  AttemptRecording r;
  r.summary.dt_s = 1e-3;
  r.summary.particle_volume_m3 = 1e-9;  // 1 mm^3
  r.summary.initial_target = 1000;
  r.summary.warning_moment_Nm = 0.2;
  r.summary.yield_moment_Nm = 0.4;
  for (int i = 0; i < 1000; ++i) {
    Frame f;
    f.t_s = (i + 1) * 1e-3;
    // Tip moves 10 mm along x in the first half second, then rests.
    f.tip_m = Vec3(i < 500 ? i * 2e-5 : 500 * 2e-5, 0, 0);
    f.nucleus_force_N = Vec3(0, 0, i == 300 ? 1.5 : 0.5);
    f.contact_force_N = Vec3(i == 700 ? 2.0 : 0.0, 0, 0);
    f.bending_moment_Nm = (i >= 100 && i < 150) ? 0.25 : 0.05;
    f.removed_target = i / 4;
    r.frames.push_back(f);
  }
  r.events.push_back({0.1, EventKind::kOverloadWarning, 0.25, "x"});
  return r;
}

TEST(Metrics, KnownValues) {
  const Metrics m = compute_metrics(synthetic());
  auto get = [&](const char* name) {
    const double* v = m.find(name);
    EXPECT_NE(v, nullptr) << name;
    return v ? *v : -1.0;
  };
  EXPECT_DOUBLE_EQ(get("nucleus_removed_mm3"), 249.0);
  EXPECT_DOUBLE_EQ(get("nucleus_removed_fraction"), 0.249);
  EXPECT_NEAR(get("peak_instrument_force_N"), std::hypot(2.0, 0.5), 1e-12);
  EXPECT_DOUBLE_EQ(get("peak_contact_force_N"), 2.0);
  EXPECT_DOUBLE_EQ(get("peak_bending_moment_Nm"), 0.25);
  EXPECT_DOUBLE_EQ(get("overload_events"), 1.0);
  EXPECT_NEAR(get("time_over_warning_s"), 0.05, 1e-12);
  EXPECT_NEAR(get("tip_path_length_mm"), 10.0, 1e-9);  // 500 steps of 0.02 mm
  EXPECT_DOUBLE_EQ(get("duration_s"), 1.0);
  EXPECT_NEAR(get("idle_time_s"), 0.499, 1e-9);  // steps 501..999 do not move
}

TEST(Metrics, EmptyRecordIsAllZero) {
  const Metrics m = compute_metrics(AttemptRecording{});
  for (const auto& [name, value] : m.values) EXPECT_EQ(value, 0.0) << name;
}

}  // namespace
}  // namespace acdr

#include "assessment/metric_catalog.hpp"

namespace acdr {
namespace {

TEST(MetricCatalog, ListsExactlyWhatComputeMetricsProduces) {
  const Metrics m = compute_metrics(AttemptRecording{});
  std::vector<std::string> produced;
  for (const auto& [name, value] : m.values) produced.push_back(name);
  EXPECT_EQ(produced, known_metric_names());
}

}  // namespace
}  // namespace acdr
