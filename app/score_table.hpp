// An attempt's metrics against their benchmarks, as every table of them shows it (the score
// screen at the end of an attempt, the dashboard's drill-down, the terminal summary of `acdr
// run`): one row per metric with its value, how the rubric judged it (scored against the
// experts, held to a safety gate, or not assessed), its benchmark and its score. Plain data:
// the views draw the rows (ui/score_table_view.hpp), the command line prints them.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "assessment/attempt_result.hpp"
#include "assessment/metric_labels.hpp"  // metric_label, for the rows
#include "assessment/rubric.hpp"

namespace acdr {

/// How the rubric judged a metric.
enum class MetricJudgement {
  kScored,       ///< a term of the composite score, against the experts' mean and spread
  kGated,        ///< a safety gate: must stay at or below its maximum
  kNotAssessed,  ///< recorded, not judged
};

struct ScoreTableRow {
  std::string metric;  ///< id, e.g. "peak_instrument_force_N"
  std::string label;   ///< in words, e.g. "Peak instrument force (N)"
  double value = 0.0;
  MetricJudgement judgement = MetricJudgement::kNotAssessed;
  double score = 0.0;     ///< kScored: 0..100
  double gate_max = 0.0;  ///< kGated: the most allowed
  /// kScored: at or better than the experts' mean (score >= 50); kGated: held; else true.
  bool good = true;
  std::optional<RubricTerm> benchmark;  ///< kScored, when the rubric is known
  bool safety = false;    ///< kScored: a Risk & Safety term (earned only when the task was done)
  bool withheld = false;  ///< kScored: a safety term scored 0 because the task was not done
  /// The attempt recorded the metric; when not, `value` is 0 and says nothing (a rubric that
  /// names a metric the scene does not measure: scored 0, its gate failed).
  bool measured = true;
};

/// Which metrics a table lists.
enum class ScoreTableScope {
  kAssessed,    ///< the scored terms, then the safety gates, as `score` lists them
  kAllMetrics,  ///< every metric of `metrics` once, in its order (a scored metric as scored)
};

/// The rows of `score` (and, for kAllMetrics, `metrics`), with each scored metric's benchmark
/// from `rubric` (null: not known).
std::vector<ScoreTableRow> score_table(const Metrics& metrics, const ScoreResult& score,
                                       const Rubric* rubric, ScoreTableScope scope);

/// The benchmark column: "experts 0.15 ± 0.05, higher is better" (scored), "at most 0"
/// (gated), "benchmark unknown" (scored, rubric not known), "" (not assessed).
std::string benchmark_text(const ScoreTableRow& row);

/// How to read the scores, in a few short sentences for the score screen, the dashboard and the
/// terminal: 50 is the experts' mean, one expert standard deviation is 10 points, what "higher
/// is better" and "lower is better" mean, how the composite is formed, and (when the rubric has
/// safety terms) that they are earned only by doing the task. `rubric` null: the general text.
std::vector<std::string> score_scale_text(const Rubric* rubric);


}  // namespace acdr
