// How a scenario turns metrics into a score and a pass/fail (plain data; the scenario loader
// fills it, assessment applies it).
#pragma once

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
  double pass_score = 50.0;            ///< composite score needed to pass
  int consecutive_passes_to_master = 2;  ///< FLS / MScore proficiency rule
};

}  // namespace acdr
