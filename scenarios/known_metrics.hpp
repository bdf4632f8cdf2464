// Metric names a rubric may refer to. A rubric term or gate on a misspelt metric would silently
// never score, so the loader accepts only names the assessment computes. Grows with assessment/
// (issue 6 adds zone, bone-contact and path metrics); keep scenario.schema.json's enum in step.
#pragma once

#include <string>
#include <vector>

namespace acdr {

/// The v1 metrics (issue 2's result JSON): nucleus_removed_mm3, nucleus_removed_fraction,
/// peak_instrument_force_N, peak_bending_moment_Nm, overload_events.
const std::vector<std::string>& known_metric_names();

}  // namespace acdr
