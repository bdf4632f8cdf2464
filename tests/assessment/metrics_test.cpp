// Metrics over a synthetic record with known answers.
#include "assessment/metrics.hpp"

#include <gtest/gtest.h>
#include <cmath>

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
  std::vector<std::string> fixed;
  for (const MetricInfo& info : metric_catalog()) fixed.push_back(info.name);
  EXPECT_EQ(produced, fixed);
  // The bone's follow them in the names a rubric may use.
  std::vector<std::string> known = fixed;
  for (const MetricInfo& info : lump_metric_catalog()) known.push_back(info.name);
  for (const MetricInfo& info : bone_metric_catalog()) known.push_back(info.name);
  EXPECT_EQ(known, known_metric_names());
  EXPECT_TRUE(is_bone_metric_name("endplate_peak_stress_MPa"));
  EXPECT_FALSE(is_bone_metric_name("peak_contact_force_N"));
}

TEST(MetricCatalog, ZoneIdsAreSafeAndUnique) {
  EXPECT_EQ(zone_metric_ids({"Vertebral artery (L)", "nerve_root_left", "", "  ", "a--b",
                             "nerve root left", "Nerve Root Left"}),
            (std::vector<std::string>{"vertebral_artery_l", "nerve_root_left", "zone2", "zone3",
                                      "a_b", "nerve_root_left_2", "nerve_root_left_3"}));
  EXPECT_EQ(zone_metric_name("cord", "dwell_s"), "zone.cord.dwell_s");
}

TEST(MetricCatalog, KnowsFixedAndZoneNamesOnly) {
  EXPECT_TRUE(is_known_metric_name("peak_contact_force_N"));
  EXPECT_TRUE(is_known_metric_name("never_events"));
  EXPECT_TRUE(is_known_metric_name("zone.vertebral_artery_left.peak_force_N"));
  EXPECT_TRUE(is_known_metric_name("zone.zone0.never_event"));
  EXPECT_FALSE(is_known_metric_name("zone.vertebral_artery_left.peak_force"));  // no unit
  EXPECT_FALSE(is_known_metric_name("zone.Vertebral.dwell_s"));  // ids are lower case
  EXPECT_FALSE(is_known_metric_name("zone..dwell_s"));
  EXPECT_FALSE(is_known_metric_name("peak_force_N"));
  for (const MetricInfo& q : zone_metric_catalog())
    EXPECT_TRUE(is_known_metric_name(zone_metric_name("x_1", q.name))) << q.name;
}

}  // namespace
}  // namespace acdr

// Zone metrics over a synthetic record whose answers follow by counting frames (dt = 1 ms).
namespace acdr {
namespace {

AttemptRecording zone_record() {
  AttemptRecording r;
  r.summary.dt_s = 1e-3;
  r.summary.zones = {{"Vertebral artery (L)", 2e-3, 1.0, true}, {"nerve root", 2e-3, 1.0, false}};
  for (int i = 0; i < 1000; ++i) {
    Frame f;
    f.t_s = (i + 1) * 1e-3;
    f.zone_count = 2;
    // Zone 0: near for frames [100, 300), inside for [200, 250) and [270, 280); 2 N while in
    // [200, 250) (above its 1 N limit), 0.5 N elsewhere near, 0 when far.
    Frame::ZoneState& a = f.zones[0];
    a.warning = i >= 100 && i < 300;
    a.inside = (i >= 200 && i < 250) || (i >= 270 && i < 280);
    a.distance_m = a.inside ? -0.5e-3f : (a.warning ? 1e-3f : 5e-3f);
    a.force_N = a.warning ? (i >= 200 && i < 250 ? 2.0f : 0.5f) : 0.0f;
    // Zone 1: near only for frames [500, 510) at 1.5 mm with 0.25 N.
    Frame::ZoneState& b = f.zones[1];
    b.warning = i >= 500 && i < 510;
    b.distance_m = b.warning ? 1.5e-3f : 3e-3f;
    b.force_N = b.warning ? 0.25f : 0.0f;
    r.frames.push_back(f);
  }
  return r;
}

TEST(ZoneMetrics, KnownValues) {
  const Metrics m = compute_metrics(zone_record());
  auto get = [&](const std::string& name) {
    const double* v = m.find(name);
    EXPECT_NE(v, nullptr) << name;
    return v ? *v : -1.0;
  };
  const std::string a = "zone.vertebral_artery_l.", b = "zone.nerve_root.";
  EXPECT_DOUBLE_EQ(get(a + "peak_force_N"), 2.0);
  EXPECT_NEAR(get(a + "impulse_Ns"), 50 * 2.0e-3 + 150 * 0.5e-3, 1e-12);
  EXPECT_NEAR(get(a + "dwell_s"), 0.2, 1e-12);
  EXPECT_NEAR(get(a + "inside_s"), 0.06, 1e-12);
  EXPECT_NEAR(get(a + "closest_mm"), -0.5, 1e-6);  // stored as float metres
  EXPECT_EQ(get(a + "warnings"), 1.0);
  EXPECT_EQ(get(a + "entries"), 2.0);
  EXPECT_EQ(get(a + "over_limit_events"), 1.0);
  EXPECT_EQ(get(a + "never_event"), 1.0);
  EXPECT_DOUBLE_EQ(get(b + "peak_force_N"), 0.25);
  EXPECT_NEAR(get(b + "impulse_Ns"), 10 * 0.25e-3, 1e-12);
  EXPECT_NEAR(get(b + "dwell_s"), 0.01, 1e-12);
  EXPECT_EQ(get(b + "inside_s"), 0.0);
  EXPECT_NEAR(get(b + "closest_mm"), 1.5, 1e-6);
  EXPECT_EQ(get(b + "entries"), 0.0);
  EXPECT_EQ(get(b + "never_event"), 0.0);
  // Sums over zones; the near intervals are disjoint, so the union is the sum.
  EXPECT_NEAR(get("zone_dwell_s"), 0.21, 1e-12);
  EXPECT_EQ(get("zone_entries"), 2.0);
  EXPECT_EQ(get("zone_warnings"), 2.0);
  EXPECT_EQ(get("zone_over_limit_events"), 1.0);
  EXPECT_EQ(get("never_events"), 2.0);
  EXPECT_DOUBLE_EQ(get("zone_peak_force_N"), 2.0);
  EXPECT_NEAR(get("zone_impulse_Ns"), 0.1775, 1e-12);
}

TEST(ZoneMetrics, OverlappingNearIntervalsCountOnceInTheUnion) {
  AttemptRecording r = zone_record();
  for (Frame& f : r.frames) f.zones[1] = f.zones[0];  // zone 1 near exactly when zone 0 is
  const Metrics m = compute_metrics(r);
  EXPECT_NEAR(*m.find("zone_dwell_s"), 0.2, 1e-12);
  EXPECT_EQ(*m.find("never_events"), 2.0);  // zone 1 is not a never-event zone
}

TEST(ZoneMetrics, NamesFollowTheCatalogueInZoneOrder) {
  const Metrics m = compute_metrics(zone_record());
  // The fixed metrics (the bone's are added only where the bone is modelled), then the zones'.
  std::vector<std::string> expected;
  for (const MetricInfo& info : metric_catalog()) expected.push_back(info.name);
  for (const char* id : {"vertebral_artery_l", "nerve_root"})
    for (const MetricInfo& q : zone_metric_catalog()) expected.push_back(zone_metric_name(id, q.name));
  std::vector<std::string> produced;
  for (const auto& [name, value] : m.values) {
    produced.push_back(name);
    EXPECT_TRUE(is_known_metric_name(name)) << name;
  }
  EXPECT_EQ(produced, expected);
}

// The other safety and economy metrics in closed form.
TEST(Metrics, ProtectedRemovedBoneContactAndIdleTime) {
  AttemptRecording r;
  r.summary.dt_s = 2e-3;
  r.summary.particle_volume_m3 = 0.125e-9;  // (0.5 mm)^3
  r.summary.warning_moment_Nm = 0.1;
  for (int i = 0; i < 500; ++i) {
    Frame f;
    f.t_s = (i + 1) * 2e-3;
    // The tip circles at radius 5 mm, one turn per 100 steps, for 200 steps; then holds.
    const double phase = 2 * 3.141592653589793 * std::min(i, 200) / 100.0;
    f.tip_m = Vec3(5e-3 * std::cos(phase), 5e-3 * std::sin(phase), 0);
    f.contact_force_N = Vec3(0, 0, 3.0 * std::sin(3.141592653589793 * i / 499.0));  // peak 3 N
    f.bending_moment_Nm = i % 4 == 0 ? 0.15 : 0.0;  // a quarter of the steps above warning
    f.removed_protected = i / 10;
    r.frames.push_back(f);
  }
  const Metrics m = compute_metrics(r);
  EXPECT_NEAR(*m.find("protected_removed_mm3"), 49 * 0.125, 1e-12);
  EXPECT_NEAR(*m.find("peak_contact_force_N"), 3.0 * std::sin(3.141592653589793 * 249 / 499.0), 1e-12);
  EXPECT_NEAR(*m.find("time_over_warning_s"), 125 * 2e-3, 1e-12);
  // 200 chords of a 100-gon of radius 5 mm: 2 turns of perimeter 100 * 2 r sin(pi / 100).
  EXPECT_NEAR(*m.find("tip_path_length_mm"), 200 * 2 * 5.0 * std::sin(3.141592653589793 / 100), 1e-9);
  EXPECT_NEAR(*m.find("idle_time_s"), 299 * 2e-3, 1e-12);  // steps 201..499 do not move
  EXPECT_NEAR(*m.find("duration_s"), 1.0, 1e-12);
}

}  // namespace
}  // namespace acdr
