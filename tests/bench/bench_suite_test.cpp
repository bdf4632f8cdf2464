// The benchmark machinery on a tiny scene (the box module on a 3 mm lattice, ~250 particles,
// 0.1 s windows): the report holds every part with the documented JSON keys, the reference's
// errors against itself are exactly zero, every other error is finite. No timing assertions.
#include "bench/bench_suite.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <sstream>

#include "bench/bench_report_format.hpp"
#include "bench/trace_error.hpp"
#include "bench/work_precision_plot.hpp"
#include "scenarios/scenario_loader.hpp"

namespace acdr {
namespace {

const std::string kBox = std::string(ACDR_SOURCE_DIR) + "/scenarios/modules/01_box_warmup.json";
const std::string kBoxPath = std::string(ACDR_SOURCE_DIR) + "/content/demonstrations/01_box_warmup/expert_1.csv";

BenchConfig tiny_config() {
  BenchConfig c;
  c.scenes.push_back({"box", kBox, kBoxPath, 1.9, 3.0e-3});
  c.scenes.back().run_from_s = 1.85;  // 50 ms before the window: a 60 ms lead (12 ms windows)
  BenchGrid& g = c.grid;
  g.window_s = 0.1;
  g.reference_dt_s = 0.5e-3;
  g.reference_tolerance = 1e-6;
  g.dts_s = {1e-3, 2e-3};
  g.tolerances = {1e-3};
  g.spacing_factors = {1.5};
  g.peer_iterations = {2};
  g.scaling_spacings_m = {4e-3, 3e-3};
  g.scaling_warmup_steps = 1;
  g.scaling_timed_steps = 2;
  g.skip_lead_s = 0.05;
  g.skip_window_s = 0.1;
  g.timing_runs = 2;
  return c;
}

// One run of the tiny benchmark serves every check below (ctest runs each TEST in its own
// process, so separate tests would each pay for the run).
const BenchReport* report_ = nullptr;

void check_parts() {
  // Reference, 2 dts x 1 tolerance, the scene's own settings, one coarser lattice, one peer.
  std::set<std::string> solvers;
  int references = 0, defaults = 0;
  for (const WorkPoint& p : report_->points) {
    solvers.insert(p.solver);
    references += p.is_reference;
    defaults += p.is_default;
    EXPECT_EQ(p.scene, "box");
    EXPECT_GT(p.particles, 0u);
    if (p.spacing_m == 3.0e-3) {
      EXPECT_GT(p.particles, 100u);
      EXPECT_LT(p.particles, 1000u);
    }
  }
  EXPECT_EQ(solvers, (std::set<std::string>{"acdr", "bullet"}));
  EXPECT_EQ(references, 1);
  EXPECT_EQ(defaults, 1);
  // 6 when the scene's own tolerance is not in the grid (the default point is added), else 5.
  EXPECT_GE(report_->points.size(), 1u + 2u + 1u + 1u);
  EXPECT_LE(report_->points.size(), 1u + 2u + 1u + 1u + 1u);
  // Every work-precision run starts 50 ms before the window, rounded up to whole sample
  // windows (5 of 12 ms).
  ASSERT_EQ(report_->windows.size(), 1u);
  EXPECT_NEAR(report_->windows[0].second.lead_s, 0.06, 1e-12);
  EXPECT_EQ(report_->scaling.size(), 2u);
  EXPECT_LT(report_->scaling[0].particles, report_->scaling[1].particles);
  ASSERT_EQ(report_->skips.size(), 4u);
  EXPECT_TRUE(report_->skips[0].measured);   // sleep
  EXPECT_TRUE(report_->skips[1].measured);   // contact culling
  EXPECT_TRUE(report_->skips[2].measured);   // undeclared parts
  EXPECT_FALSE(report_->skips[3].measured);  // headless: no renderer given
}

void check_errors() {
  for (const WorkPoint& p : report_->points) {
    SCOPED_TRACE(p.solver + " " + p.settings);
    EXPECT_TRUE(std::isfinite(p.force_rms_error));
    EXPECT_TRUE(std::isfinite(p.force_peak_error));
    EXPECT_TRUE(std::isfinite(p.removed_error));
    EXPECT_TRUE(std::isfinite(p.wall_s_per_sim_s));
    EXPECT_GE(p.force_rms_error, 0.0);
    EXPECT_GT(p.wall_s_per_sim_s, 0.0);
    if (p.is_reference) {
      EXPECT_EQ(p.force_rms_error, 0.0);
      EXPECT_EQ(p.force_peak_error, 0.0);
      EXPECT_EQ(p.removed_error, 0.0);
    } else if (p.solver == "acdr") {
      // A different step or tolerance gives a (slightly) different force history.
      EXPECT_GT(p.force_rms_error, 0.0);
      // Timed twice (identical work, so not FAILED); the time kept is the faster one.
      EXPECT_EQ(p.timing_runs, 2);
      EXPECT_FALSE(p.failed);
      EXPECT_GE(p.slowest_wall_s_per_sim_s, p.wall_s_per_sim_s);
    }
    if (p.solver == "acdr") {
      // Step times: the 99th percentile is at least the typical step, at most the slowest.
      EXPECT_GT(p.mean_step_ms, 0.0);
      EXPECT_GT(p.p99_step_ms, 0.0);
      EXPECT_GT(p.cpu_us_per_particle_step, 0.0);
    }
  }
  for (const SkipResult& s : report_->skips) {
    if (!s.measured) continue;
    EXPECT_TRUE(std::isfinite(s.force_rms_error)) << s.name;
    EXPECT_TRUE(std::isfinite(s.gain)) << s.name;
  }
  EXPECT_TRUE(std::isfinite(report_->scaling_fit.exponent));
}

void check_json() {
  const nlohmann::json j = bench_report_json(*report_);
  ASSERT_TRUE(j.contains("points"));
  ASSERT_TRUE(j.contains("scaling"));
  ASSERT_TRUE(j.contains("skips"));
  ASSERT_EQ(j["points"].size(), report_->points.size());
  for (const auto& p : j["points"]) {
    for (const char* key : {"scene", "solver", "settings", "wall_s_per_sim_s",
                            "force_rms_error", "removed_error", "mean_step_ms", "p99_step_ms",
                            "cpu_us_per_particle_step"})
      EXPECT_TRUE(p.contains(key)) << key;
    EXPECT_TRUE(p["solver"] == "acdr" || p["solver"] == "bullet");
    EXPECT_TRUE(p["settings"].is_object());
  }
  EXPECT_NEAR(j["windows"]["box"]["lead_s"].get<double>(), 0.06, 1e-12);
  EXPECT_TRUE(j["scaling"].contains("exponent"));
  EXPECT_TRUE(j["scaling"]["points"].is_array());
  for (const auto& p : j["scaling"]["points"]) EXPECT_TRUE(p.contains("cpu_us_per_particle_step"));
  EXPECT_EQ(j["skips"].size(), 4u);
  // Table and CSV name every point.
  std::ostringstream table, csv;
  write_bench_table(*report_, table);
  write_bench_csv(*report_, csv);
  EXPECT_NE(table.str().find("bullet"), std::string::npos);
  std::size_t rows = 0;
  for (char ch : csv.str()) rows += ch == '\n';
  EXPECT_GE(rows, 1u + report_->points.size() + report_->scaling.size());
}

void check_plot() {
  const PlotImage img = plot_work_precision(*report_, 800, 500);
  ASSERT_EQ(img.rgb.size(), 800u * 500u * 3u);
  // Something besides the white background is drawn.
  std::size_t ink = 0;
  for (std::uint8_t v : img.rgb) ink += v < 128;
  EXPECT_GT(ink, 1000u);
}

TEST(BenchSuite, TinyBoxRunHoldsEveryPartWithZeroReferenceErrorAndTheDocumentedKeys) {
  BenchReport report;
  std::string error;
  ASSERT_TRUE(run_bench_suite(tiny_config(), &report, &error)) << error;
  report_ = &report;
  {
    SCOPED_TRACE("parts");
    check_parts();
  }
  {
    SCOPED_TRACE("errors");
    check_errors();
  }
  {
    SCOPED_TRACE("json, table, csv");
    check_json();
  }
  {
    SCOPED_TRACE("plot");
    check_plot();
  }
  report_ = nullptr;
}

TEST(FitPower, RecoversAnExponent) {
  const std::vector<double> n{1e3, 4e3, 1.6e4, 6.4e4};
  std::vector<double> cost;
  for (double x : n) cost.push_back(0.02 * std::pow(x, 1.1));
  const PowerFit f = fit_power(n, cost);
  EXPECT_NEAR(f.exponent, 1.1, 1e-9);
  EXPECT_NEAR(f.coefficient, 0.02, 1e-9);
  EXPECT_NEAR(f.r2, 1.0, 1e-12);
}

TEST(TraceError, ZeroAgainstItselfAndRelativeOtherwise) {
  RunTrace a;
  a.force_N = {Vec3(1, 0, 0), Vec3(0, 2, 0)};
  a.t_s = {0.01, 0.02};
  EXPECT_EQ(trace_error(a, a).force_rms, 0.0);
  RunTrace b = a;
  b.force_N[1] = Vec3(0, 1, 0);  // |diff| = 1, sum |ref|^2 = 5
  EXPECT_NEAR(trace_error(b, a).force_rms, std::sqrt(1.0 / 5.0), 1e-12);
  EXPECT_NEAR(trace_error(b, a).force_peak, 0.5, 1e-12);
}

}  // namespace
}  // namespace acdr
