// Turns metrics into a composite score and a pass decision under a scenario's rubric.
#pragma once

#include "assessment/attempt_result.hpp"
#include "assessment/rubric.hpp"

namespace acdr {

/// Composite = weighted mean over terms of clip(50 + 10*z, 0, 100), z the metric's distance
/// from the expert mean in expert SDs (sign so that better is higher); a safety term scores 0
/// unless the attempt did the task (rubric.task). Passes when the task was done, the composite
/// reaches pass_score, every gate holds, no numerical failure occurred and no never-event zone
/// was entered (metric never_events = 0).
ScoreResult score_attempt(const Metrics& metrics, const Rubric& rubric);

}  // namespace acdr
