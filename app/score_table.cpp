// Rows of the score table.
#include "app/score_table.hpp"

#include <cstdio>
#include <utility>

#include "assessment/metric_labels.hpp"

namespace acdr {
namespace {

std::string format(const char* fmt, double a, double b = 0.0) {
  char text[128];
  std::snprintf(text, sizeof text, fmt, a, b);
  return text;
}

template <class T>
const T* find_metric(const std::vector<T>& items, const std::string& metric) {
  for (const T& item : items)
    if (item.metric == metric) return &item;
  return nullptr;
}

ScoreTableRow scored_row(const TermScore& term, const Rubric* rubric) {
  ScoreTableRow row;
  row.metric = term.metric;
  row.label = metric_label(term.metric);
  row.value = term.value;
  row.judgement = MetricJudgement::kScored;
  row.score = term.score;
  row.good = term.score >= 50.0;
  row.safety = term.safety;
  row.withheld = term.withheld;
  if (rubric)
    if (const RubricTerm* r = find_metric(rubric->terms, term.metric)) {
      row.benchmark = *r;
      row.safety = row.safety || r->safety;  // a stored score does not keep the group
    }
  return row;
}

ScoreTableRow gated_row(const GateResult& gate) {
  ScoreTableRow row;
  row.metric = gate.metric;
  row.label = metric_label(gate.metric);
  row.value = gate.value;
  row.judgement = MetricJudgement::kGated;
  row.gate_max = gate.max;
  row.good = gate.passed;
  return row;
}

}  // namespace

std::vector<ScoreTableRow> score_table(const Metrics& metrics, const ScoreResult& score,
                                       const Rubric* rubric, ScoreTableScope scope) {
  std::vector<ScoreTableRow> rows;
  if (scope == ScoreTableScope::kAssessed) {
    for (const TermScore& t : score.terms) rows.push_back(scored_row(t, rubric));
    for (const GateResult& g : score.gates) rows.push_back(gated_row(g));
    for (ScoreTableRow& row : rows) row.measured = metrics.find(row.metric) != nullptr;
    return rows;
  }
  for (const auto& [name, value] : metrics.values) {
    ScoreTableRow row;
    if (const TermScore* t = find_metric(score.terms, name)) {
      row = scored_row(*t, rubric);
    } else if (const GateResult* g = find_metric(score.gates, name)) {
      row = gated_row(*g);
    } else {
      row.metric = name;
      row.label = metric_label(name);
    }
    row.value = value;  // as recorded
    rows.push_back(std::move(row));
  }
  return rows;
}

std::string benchmark_text(const ScoreTableRow& row) {
  switch (row.judgement) {
    case MetricJudgement::kScored:
      if (!row.benchmark) return "benchmark unknown";
      return format("experts %.3g ± %.2g, ", row.benchmark->expert_mean,
                    row.benchmark->expert_sd) +
             (row.benchmark->higher_is_better ? "higher is better" : "lower is better") +
             (row.withheld ? "; task not done: 0" : "");
    case MetricJudgement::kGated: return format("at most %.3g", row.gate_max);
    case MetricJudgement::kNotAssessed: break;
  }
  return "";
}

std::vector<std::string> score_scale_text(const Rubric* rubric) {
  std::vector<std::string> lines = {
      "50 = the experts' mean; each expert standard deviation (SD) better or worse is 10 points "
      "more or less (0-100).",
      "\"Higher is better\": more of the metric scores more (nucleus removed); \"lower is "
      "better\": less scores more (force, time near a zone). Where the experts' mean is 0, 50 "
      "is the best there is: as safe as the experts.",
  };
  std::string composite = "The score is the weighted mean of the metric scores";
  if (rubric) composite += format("; pass at %.0f", rubric->pass_score);
  composite += ", with every safety gate held and no never-event.";
  lines.push_back(composite);
  if (rubric && rubric->task)
    lines.push_back("Safety metrics are earned only by doing the task (" +
                    metric_label(rubric->task->metric) + format(" at least %.3g", rubric->task->min) +
                    "); otherwise they score 0.");
  return lines;
}

}  // namespace acdr
