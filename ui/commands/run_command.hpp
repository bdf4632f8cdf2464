// `acdr run SCENARIO`: one attempt, scored, stored, optionally pictured.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>

namespace acdr {

struct RunOptions {
  std::string scenario;
  std::string input = "replay:";  ///< replay:FILE (mouse and udp:PORT come with the devices)
  std::optional<std::string> trainee;  ///< none: a practice attempt
  bool override_lock = false;     ///< an instructor lets the trainee take a locked module
  std::string override_by;        ///< who decided (required with override_lock)
  std::string override_reason;
  std::string db;                 ///< empty: default_database_path()
  std::string png;                ///< final frame picture, when set
  std::string record;             ///< also write the recording to this file, when set
  bool json = false;
  bool headless = true;
  int png_width = 1280;
  int png_height = 800;
};

/// Exit codes: 0 attempt completed (passed or not), 1 the simulation failed numerically,
/// 2 bad input (scenario, trajectory, database), 3 the module is locked for this trainee.
int run_run(const RunOptions& options, std::ostream& out, std::ostream& err);

}  // namespace acdr
