// Tests of app/score_table: the rows every table of an attempt's metrics shows — the scored
// terms then the gates (score screen, terminal), or every recorded metric once (dashboard) —
// with their judgement, benchmark and verdict, and the labels and benchmark texts.
#include "app/score_table.hpp"

#include <gtest/gtest.h>

namespace acdr {
namespace {

Rubric rubric() {
  Rubric r;
  r.terms.push_back({"nucleus_removed_fraction", 0.15, 0.05, true, 1.0});
  r.terms.push_back({"peak_instrument_force_N", 1.5, 0.5, false, 1.0});
  r.gates.push_back({"overload_events", 0.0});
  return r;
}

// A weak removal, a good force, a failed gate; tip path recorded but not judged.
void failing_attempt(Metrics& metrics, ScoreResult& score) {
  metrics.set("nucleus_removed_fraction", 0.05);
  metrics.set("tip_path_length_mm", 88.0);
  metrics.set("overload_events", 2.0);
  metrics.set("peak_instrument_force_N", 1.0);
  score.terms = {{"nucleus_removed_fraction", 0.05, 30.0}, {"peak_instrument_force_N", 1.0, 60.0}};
  score.gates = {{"overload_events", 2.0, 0.0, false}};
}

TEST(ScoreTable, AssessedRowsAreTheTermsThenTheGates) {
  Metrics metrics;
  ScoreResult score;
  failing_attempt(metrics, score);
  const Rubric r = rubric();
  const auto rows = score_table(metrics, score, &r, ScoreTableScope::kAssessed);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].metric, "nucleus_removed_fraction");
  EXPECT_EQ(rows[0].judgement, MetricJudgement::kScored);
  EXPECT_EQ(rows[0].score, 30.0);
  EXPECT_FALSE(rows[0].good);  // below the experts' mean
  ASSERT_TRUE(rows[0].benchmark);
  EXPECT_EQ(rows[0].benchmark->expert_mean, 0.15);
  EXPECT_TRUE(rows[1].good);
  EXPECT_EQ(rows[2].metric, "overload_events");
  EXPECT_EQ(rows[2].judgement, MetricJudgement::kGated);
  EXPECT_EQ(rows[2].value, 2.0);
  EXPECT_EQ(rows[2].gate_max, 0.0);
  EXPECT_FALSE(rows[2].good);
  EXPECT_EQ(rows[2].label, "Shaft overload warnings");
}

TEST(ScoreTable, AMetricTheAttemptDidNotRecordIsMarkedNotMeasured) {
  Metrics metrics;
  ScoreResult score;
  failing_attempt(metrics, score);
  // A gate on a zone the scene does not have: scoring failed it with the value 0.
  score.gates.push_back({"zone.osteophyte.warnings", 0.0, 0.0, false});
  const Rubric r = rubric();
  const auto rows = score_table(metrics, score, &r, ScoreTableScope::kAssessed);
  ASSERT_EQ(rows.size(), 4u);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_TRUE(rows[i].measured) << rows[i].metric;
  EXPECT_FALSE(rows[3].measured);
  EXPECT_FALSE(rows[3].good);
}

TEST(ScoreTable, AllMetricsRowsFollowTheRecordingsOrder) {
  Metrics metrics;
  ScoreResult score;
  failing_attempt(metrics, score);
  const Rubric r = rubric();
  const auto rows = score_table(metrics, score, &r, ScoreTableScope::kAllMetrics);
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0].judgement, MetricJudgement::kScored);
  EXPECT_EQ(rows[1].metric, "tip_path_length_mm");
  EXPECT_EQ(rows[1].judgement, MetricJudgement::kNotAssessed);
  EXPECT_EQ(rows[1].value, 88.0);
  EXPECT_TRUE(rows[1].good);
  EXPECT_EQ(rows[2].judgement, MetricJudgement::kGated);
  EXPECT_EQ(rows[3].metric, "peak_instrument_force_N");
  EXPECT_EQ(rows[3].judgement, MetricJudgement::kScored);
}

TEST(ScoreTable, BenchmarkTextsSayWhatEachRowIsHeldTo) {
  Metrics metrics;
  ScoreResult score;
  failing_attempt(metrics, score);
  const Rubric r = rubric();
  const auto rows = score_table(metrics, score, &r, ScoreTableScope::kAllMetrics);
  EXPECT_EQ(benchmark_text(rows[0]), "experts 0.15 ± 0.05, higher is better");
  EXPECT_EQ(benchmark_text(rows[1]), "");
  EXPECT_EQ(benchmark_text(rows[2]), "at most 0");
  EXPECT_EQ(benchmark_text(rows[3]), "experts 1.5 ± 0.5, lower is better");
  // Without the rubric a scored metric keeps its score but not its benchmark.
  const auto unknown = score_table(metrics, score, nullptr, ScoreTableScope::kAssessed);
  EXPECT_FALSE(unknown[0].benchmark);
  EXPECT_EQ(unknown[0].score, 30.0);
  EXPECT_EQ(benchmark_text(unknown[0]), "benchmark unknown");
}

TEST(ScoreTable, RowsCarryTheCataloguesLabels) {
  Metrics metrics;
  metrics.values = {{"zone.spinal_cord_pll.peak_force_N", 0.4}, {"duration_s", 3.0}};
  const auto rows = score_table(metrics, ScoreResult{}, nullptr, ScoreTableScope::kAllMetrics);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].label, "Spinal cord / PLL: peak force near it (N)");
  EXPECT_EQ(rows[1].label, "Duration (s)");
}

// The scale, in words every screen shows: 50, 10 points per SD, the direction, the task rule.
TEST(ScoreTable, TheScaleIsExplained) {
  Rubric r;
  r.pass_score = 60;
  r.task = TaskRule{"nucleus_removed_fraction", 0.18};
  const std::vector<std::string> lines = score_scale_text(&r);
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_NE(lines[0].find("50 = the experts' mean"), std::string::npos);
  EXPECT_NE(lines[0].find("standard deviation (SD) better or worse is 10 points"), std::string::npos)
      << lines[0];
  EXPECT_NE(lines[1].find("\"Higher is better\": more of the metric scores more"), std::string::npos)
      << lines[1];
  EXPECT_NE(lines[2].find("pass at 60"), std::string::npos) << lines[2];
  EXPECT_EQ(lines[3],
            "Safety metrics are earned only by doing the task (Nucleus removed (fraction) at least "
            "0.18); otherwise they score 0.");
  EXPECT_EQ(score_scale_text(nullptr).size(), 3u);
}

}  // namespace
}  // namespace acdr
