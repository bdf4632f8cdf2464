// `acdr dashboard`: the instructor dashboard in a window, or one offscreen picture of it
// (`--screenshot FILE`), or the CSV of a view (`--export-csv FILE`).
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>

namespace acdr {

struct DashboardOptions {
  std::string db;          ///< empty: default_database_path()
  std::string screenshot;  ///< render one frame offscreen to this PNG and exit
  std::string export_csv;  ///< write the selected view's CSV to this file and exit
  int width = 1600;        ///< window or picture size (pixels)
  int height = 1200;
  std::string trainee;     ///< select this trainee (default: the first with attempts)
  std::string module;      ///< the learning curve's module (default: of the latest attempt)
  std::int64_t attempt = -1;  ///< open this attempt (default: the latest completed; 0: none)
  double replay_t_s = -1.0;   ///< replay cursor (default: 60 % through the attempt)
  std::string export_dir = ".";  ///< where the window's "Export CSV" writes
};

/// Exit codes: 0 ok, 1 the database cannot be read, 2 bad options (unknown trainee or
/// attempt, unwritable file, no display for a window).
int run_dashboard(const DashboardOptions& options, std::ostream& out, std::ostream& err);

}  // namespace acdr
