// How a scenario turns metrics into a score and a pass/fail (plain data; the scenario loader
// fills it, assessment applies it).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace acdr {

/// A scored metric: z = (value - expert_mean) / expert_sd (sign flipped when lower is better),
/// scored 50 + 10*z clipped to [0, 100] (UCSF ATOSS convention, docs/references.md).
struct RubricTerm {
  std::string metric;
  double expert_mean = 0.0;
  double expert_sd = 1.0;
  bool higher_is_better = true;
  double weight = 1.0;
  /// A Risk & Safety term (as the da Vinci MScore groups its metrics): it scores only when the
  /// attempt did the task (Rubric::task); otherwise 0, so staying away from the anatomy by
  /// doing nothing earns nothing.
  bool safety = false;
  /// The smallest expert_sd a calibration from an expert cohort may set
  /// (assessment/calibration.hpp): where the experts agree exactly (none goes near a danger
  /// zone, so their zone time is 0 s with SD 0), the floor says what difference is worth one
  /// SD. 0: none (the experts must differ). Scoring does not read it.
  double sd_floor = 0.0;
};

/// What "did the task" means: the metric reached `min` (e.g. nucleus_removed_fraction at
/// least a quarter of the experts' mean). Safety terms, and every other term but the one on
/// the task's own metric (time, say), score only then.
struct TaskRule {
  std::string metric;
  double min = 0.0;
};

/// A safety gate: the metric must stay at or below `max` for the attempt to pass,
/// whatever the composite score (da Vinci MScore: every metric must pass).
struct SafetyGate {
  std::string metric;
  double max = 0.0;
};

struct Rubric {
  std::vector<RubricTerm> terms;
  std::vector<SafetyGate> gates;
  /// Required when any term is a safety term; none: every attempt counts as having done it.
  std::optional<TaskRule> task;
  double pass_score = 50.0;            ///< composite score needed to pass
  int consecutive_passes_to_master = 2;  ///< FLS / MScore proficiency rule
};

}  // namespace acdr
