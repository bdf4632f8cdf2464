// Rows of the score table.
#include "app/score_table.hpp"

#include <cctype>
#include <cstdio>
#include <utility>

#include "assessment/zone_findings.hpp"

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

std::string metric_label(const std::string& metric) {
  // Known metrics with hand-written labels; others are derived from the name.
  static const std::vector<std::pair<std::string, std::string>> kLabels = {
      {"nucleus_removed_fraction", "Nucleus removed (fraction)"},
      {"nucleus_removed_mm3", "Nucleus removed (mm³)"},
      {"protected_removed_mm3", "Annulus/endplate removed (mm³)"},
      {"peak_instrument_force_N", "Peak instrument force (N)"},
      {"instrument_force_impulse_Ns", "Instrument force impulse (N·s)"},
      {"peak_contact_force_N", "Peak bone/wall contact force (N)"},
      {"peak_feedback_force_N", "Peak force on the hand (N)"},
      {"peak_bending_moment_Nm", "Peak shaft bending moment (N·m)"},
      {"overload_events", "Shaft overload warnings"},
      {"yield_events", "Shaft yield (bent) events"},
      {"time_over_warning_s", "Time over the overload warning (s)"},
      {"tip_path_length_mm", "Tip path length (mm)"},
      {"duration_s", "Duration (s)"},
      {"idle_time_s", "Idle time (s)"},
      {"zone_warnings", "Danger zone warnings"},
      {"zone_entries", "Danger zone entries"},
      {"zone_over_limit_events", "Force over a zone's limit (times)"},
      {"zone_peak_force_N", "Peak force near a danger zone (N)"},
      {"zone_impulse_Ns", "Force-time near danger zones (N·s)"},
      {"zone_dwell_s", "Time near danger zones (s)"},
      {"never_events", "Never-events"},
  };
  for (const auto& [name, label] : kLabels)
    if (name == metric) return label;
  // zone.<id>.<quantity> -> "<zone>: <quantity>", e.g. "Spinal cord / PLL: peak force (N)".
  if (metric.rfind("zone.", 0) == 0) {
    const std::size_t dot = metric.find('.', 5);
    if (dot != std::string::npos && dot + 1 < metric.size()) {
      std::string zone = zone_display_name(metric.substr(5, dot - 5));
      for (char& c : zone)
        if (c == '_') c = ' ';
      if (!zone.empty() && zone[0] >= 'a' && zone[0] <= 'z') zone[0] = static_cast<char>(zone[0] - 'a' + 'A');
      std::string quantity = metric_label(metric.substr(dot + 1));
      if (!quantity.empty() && quantity[0] >= 'A' && quantity[0] <= 'Z')
        quantity[0] = static_cast<char>(quantity[0] - 'A' + 'a');
      return zone + ": " + quantity;
    }
  }
  // snake_case_with_unit -> "Snake case with (unit)"
  std::string words = metric;
  std::string unit;
  static const char* kUnits[] = {"_mm3", "_mm", "_Ns", "_Nm", "_N", "_s", "_m"};
  for (const char* u : kUnits) {
    const std::string suffix = u;
    if (words.size() > suffix.size() &&
        words.compare(words.size() - suffix.size(), suffix.size(), suffix) == 0) {
      unit = suffix.substr(1);
      words.resize(words.size() - suffix.size());
      break;
    }
  }
  for (char& c : words)
    if (c == '_') c = ' ';
  if (!words.empty()) words[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(words[0])));
  return unit.empty() ? words : words + " (" + unit + ")";
}

}  // namespace acdr
