// The outcome of one attempt: named metrics, the composite score and the pass decision.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace acdr {

/// Named metric values, in a fixed order (deterministic output). Units in the names.
struct Metrics {
  std::vector<std::pair<std::string, double>> values;

  void set(const std::string& name, double value);
  /// Value of `name`, or nullptr when absent.
  const double* find(const std::string& name) const;
};

struct TermScore {
  std::string metric;
  double value = 0.0;
  double score = 0.0;  ///< 0..100
  bool safety = false;    ///< a Risk & Safety term (RubricTerm::safety)
  bool withheld = false;  ///< scored 0 because the task was not done (Rubric::task)
};

struct GateResult {
  std::string metric;
  double value = 0.0;
  double max = 0.0;
  bool passed = true;
};

struct ScoreResult {
  double score = 0.0;  ///< composite 0..100
  bool passed = false;
  bool task_done = true;  ///< the rubric's task rule held (true when it has none)
  std::vector<TermScore> terms;
  std::vector<GateResult> gates;
  std::vector<std::string> reasons;  ///< why it failed, in words
};

}  // namespace acdr
