// The score table drawn with Dear ImGui: metric, value, benchmark and score, one row per
// ScoreTableRow (app/score_table.hpp), in the state colours. The score screen and the
// dashboard's drill-down both draw it.
#pragma once

#include <vector>

#include "app/score_table.hpp"

namespace acdr {

/// Draws `rows` as a table with ImGui id `id` in the current window: scored rows with their
/// score (green at or above the experts' mean, amber below), gates as held (green) or FAILED
/// (red), metrics not assessed in muted text. Safety terms read "Safety: ...", gates "Gate: ...".
void draw_score_table(const char* id, const std::vector<ScoreTableRow>& rows);

}  // namespace acdr
