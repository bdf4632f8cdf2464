// The metrics assessment computes: names (with units in them), and what each means. Rubrics
// may refer only to these, so a misspelt metric never silently scores nothing.
#pragma once

#include <string>
#include <vector>

namespace acdr {

struct MetricInfo {
  std::string name;     ///< e.g. "peak_instrument_force_N"
  std::string meaning;  ///< one line, for documentation and the dashboard
};

/// Every metric compute_metrics() produces, in its output order.
const std::vector<MetricInfo>& metric_catalog();

/// Just the names, in the same order.
const std::vector<std::string>& known_metric_names();

}  // namespace acdr
