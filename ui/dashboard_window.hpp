// The instructor dashboard on screen: in a window of its own until the instructor closes it,
// or as one offscreen picture. Both draw draw_dashboard (ui/dashboard_view.hpp); the window
// also keeps the model fresh and acts on what the instructor asks for (refresh, open an
// attempt, export the current view's CSV).
#pragma once

#include <memory>
#include <string>

#include "db/database.hpp"
#include "ui/dashboard_model.hpp"

namespace acdr {

struct DashboardWindowOptions {
  int width = 1600;              ///< window size (screen coordinates)
  int height = 1200;
  std::string export_dir = ".";  ///< where "Export CSV" writes
};

/// Runs the dashboard window over `db`, starting from `model`, `selection` and its drill-down
/// `attempt` (may be null), until it is closed. The model is read again every few seconds (a
/// running attempt shares the file); a selected attempt's drill-down is loaded once, when it is
/// selected. Returns false with `error` set when the window cannot be opened or drawn.
bool run_dashboard_window(const DashboardWindowOptions& options, Database& db,
                          DashboardModel model, DashboardSelection selection,
                          std::unique_ptr<AttemptDrillDown> attempt, std::string* error);

/// Draws the dashboard offscreen at `width` x `height` pixels and writes it to `path` (PNG).
/// Returns false with `error` set (naming `path` when the picture could not be written).
bool write_dashboard_png(const DashboardModel& model, const DashboardSelection& selection,
                         const AttemptDrillDown* attempt, int width, int height,
                         const std::string& path, std::string* error);

/// Writes dashboard_csv of the current view to `path`. Returns false with `error` set.
bool write_dashboard_csv(const DashboardModel& model, const DashboardSelection& selection,
                         const AttemptDrillDown* attempt, const std::string& path,
                         std::string* error);

}  // namespace acdr
