// Composite score (UCSF ATOSS 50 + 10·z convention) and gates (every safety metric must pass
// on its own, as in the da Vinci MScore; docs/references.md, Assessment anchors).
#include "assessment/scoring.hpp"

#include <algorithm>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "assessment/metric_labels.hpp"

namespace acdr {

ScoreResult score_attempt(const Metrics& metrics, const Rubric& rubric) {
  ScoreResult r;
  // Did the attempt do the task? Safety terms are earned only then: an attempt that stays
  // clear of every danger zone by removing nothing is not safe, it is absent.
  if (rubric.task) {
    const double* done = metrics.find(rubric.task->metric);
    r.task_done = done && *done >= rubric.task->min;
    if (!r.task_done) {
      char text[240];
      if (done)
        std::snprintf(text, sizeof text,
                      "the task was not done (%s = %.3g, at least %.3g needed), so the safety "
                      "terms (and any other but the task's own) score 0",
                      rubric.task->metric.c_str(), *done, rubric.task->min);
      else
        std::snprintf(text, sizeof text,
                      "the task was not done (%s was not measured), so the safety terms (and any "
                      "other but the task's own) score 0",
                      rubric.task->metric.c_str());
      r.reasons.push_back(text);
    }
  }
  double weighted = 0, weights = 0;
  for (const RubricTerm& term : rubric.terms) {
    const double* value = metrics.find(term.metric);
    TermScore ts;
    ts.metric = term.metric;
    ts.safety = term.safety;
    if (value) ts.value = *value;
    // Only the task's own metric is scored without the task: safety, time and any other term
    // are earned by doing it (a quick attempt that removes nothing is not efficient).
    const bool earned_by_task = term.safety || (rubric.task && term.metric != rubric.task->metric);
    if (earned_by_task && !r.task_done) {
      ts.withheld = true;
      ts.score = 0;
    } else if (!value) {
      r.reasons.push_back("metric '" + term.metric + "' was not measured");
      ts.score = 0;
    } else {
      const double sd = term.expert_sd > 0 ? term.expert_sd : 1.0;
      double z = (*value - term.expert_mean) / sd;
      if (!term.higher_is_better) z = -z;
      ts.score = std::clamp(50.0 + 10.0 * z, 0.0, 100.0);
    }
    weighted += term.weight * ts.score;
    weights += term.weight;
    r.terms.push_back(ts);
  }
  r.score = weights > 0 ? weighted / weights : 0.0;

  bool gates_ok = true;
  for (const SafetyGate& gate : rubric.gates) {
    const double* value = metrics.find(gate.metric);
    GateResult g{gate.metric, value ? *value : 0.0, gate.max, value && *value <= gate.max};
    if (!g.passed) {
      gates_ok = false;
      char text[200];
      if (value)
        std::snprintf(text, sizeof text, "%s = %g is above its limit %g", gate.metric.c_str(),
                      *value, gate.max);
      else
        std::snprintf(text, sizeof text, "%s was not measured", gate.metric.c_str());
      r.reasons.push_back(text);
    }
    r.gates.push_back(g);
  }
  const double* numerical = metrics.find("numerical_events");
  const bool numerics_ok = !numerical || *numerical == 0;
  if (!numerics_ok) r.reasons.push_back("the simulation reported numerical trouble");
  // Any never-event fails the attempt, whatever the rubric says (the zones that
  // were entered are named by their zone.<id>.never_event metrics).
  const double* never = metrics.find("never_events");
  const bool never_ok = !never || *never == 0;
  if (!never_ok) {
    std::string zones;
    const std::string suffix = ".never_event";
    for (const auto& [name, value] : metrics.values) {
      if (value == 0 || name.rfind("zone.", 0) != 0 || name.size() <= suffix.size() + 5 ||
          name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
        continue;
      // By the zone's name in words (the record keeps the id in the metric's name).
      const std::string zone = zone_display_name(name.substr(5, name.size() - 5 - suffix.size()));
      zones += (zones.empty() ? "the " : ", the ") + zone +
               (zone.find("zone") == std::string::npos ? " zone" : "");
    }
    r.reasons.push_back("never-event: the instrument entered " +
                        (zones.empty() ? std::string("a never-event zone") : zones));
  }
  if (r.score < rubric.pass_score) {
    char text[120];
    std::snprintf(text, sizeof text, "composite score %.1f is below the pass score %.1f", r.score,
                  rubric.pass_score);
    std::string reason = text;
    // Name what pulled it down: the terms two or more expert SDs on the wrong side of the
    // experts' mean (time, removal, force, ...), worst first, at most three. Terms withheld for
    // want of the task count too: an attempt that ran out of time with too little removed is
    // told it was slow, not only that it removed too little.
    std::vector<std::pair<double, std::string>> weak;
    for (std::size_t i = 0; i < rubric.terms.size(); ++i) {
      const RubricTerm& term = rubric.terms[i];
      const TermScore& ts = r.terms[i];
      if (metrics.find(term.metric) == nullptr) continue;
      const double sd = term.expert_sd > 0 ? term.expert_sd : 1.0;
      double z = (ts.value - term.expert_mean) / sd;
      if (!term.higher_is_better) z = -z;
      if (z <= -2.0) {
        char part[240];
        std::snprintf(part, sizeof part, "%s %.3g against the experts' %.3g ± %.2g (%.1f SD %s)",
                      metric_label(term.metric).c_str(), ts.value, term.expert_mean, sd, -z,
                      term.higher_is_better ? "below" : "above");
        weak.emplace_back(z, part);
      }
    }
    std::sort(weak.begin(), weak.end());
    for (std::size_t i = 0; i < weak.size() && i < 3; ++i)
      reason += (i == 0 ? "; furthest from the experts: " : ", ") + weak[i].second;
    r.reasons.push_back(reason);
  }
  r.passed = r.task_done && gates_ok && numerics_ok && never_ok && r.score >= rubric.pass_score;
  return r;
}

}  // namespace acdr
