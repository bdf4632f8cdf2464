// Metrics of an attempt, computed only from its record (frames and events).
// Definitions in docs/assessment.md.
#pragma once

#include "assessment/attempt_recording.hpp"
#include "assessment/attempt_result.hpp"

namespace acdr {

/// Tip speed below which the instrument counts as idle (m/s).
inline constexpr double kIdleSpeed_m_s = 1.0e-3;

Metrics compute_metrics(const AttemptRecording& record);

}  // namespace acdr
