// The instructor dashboard drawn with Dear ImGui from a DashboardModel (ui/dashboard_model.hpp):
// a trainee list; the curriculum progress matrix (trainee x module: locked, not started, in
// progress, passed, mastered); the selected trainee's learning curve (score per attempt with
// the pass line and the progression rule's state); and the selected attempt's drill-down:
// metrics against benchmarks, force over time with overload and input bands, the event
// timeline, and a replay of the recorded instrument with a time scrubber. The same function
// draws into the window and into `acdr dashboard --screenshot` pictures.
#pragma once

#include <string>

#include <imgui.h>

#include "ui/dashboard_model.hpp"

namespace acdr {

/// What the instructor asked for this frame.
struct DashboardActions {
  bool refresh = false;             ///< read the record again
  bool export_csv = false;          ///< write the current view's CSV
  bool attempt_changed = false;     ///< selection.attempt_id changed: load its drill-down
};

/// Draws the dashboard over the whole display. `attempt` is the drill-down of
/// selection.attempt_id when loaded (null otherwise); `status` is a line for the footer (last
/// export, errors).
void draw_dashboard(const DashboardModel& model, DashboardSelection& selection,
                    const AttemptDrillDown* attempt, const std::string& status,
                    const ImVec2& display, DashboardActions* actions);

}  // namespace acdr
