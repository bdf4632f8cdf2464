// The bone-stress metrics of an attempt (names in bone_metric_catalog(), definitions in
// docs/assessment.md) from the summary of its bone load samples (engine/bone).
#pragma once

#include "assessment/attempt_result.hpp"
#include "engine/bone/bone_stress_summary.hpp"

namespace acdr {

/// Appends the bone metrics, in bone_metric_catalog() order.
void add_bone_metrics(const BoneStressSummary& summary, Metrics& metrics);

}  // namespace acdr
