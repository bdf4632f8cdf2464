// `acdr run SCENARIO`: one attempt (the attempt session, app/attempt_session.hpp), in the
// trainee view's window when a display exists, then pictured and reported.
#pragma once

#include <iosfwd>
#include <string>

#include "app/attempt_session.hpp"

namespace acdr {

/// The session's options, and how the command shows the attempt.
struct RunOptions : SessionOptions {
  std::string png;                ///< final frame picture, when set
  bool json = false;
  /// No window. Without this flag a window opens when a display exists (else the run is
  /// headless, with a note on stderr).
  bool headless = false;
  int png_width = 1280;
  int png_height = 800;
  /// Draw the particle materials as beads (a debug view of the particles) instead of surfaces,
  /// in the window and the picture.
  bool beads = false;
  /// Window only: picture of the window (PNG) at `screenshot_at_s` (< 0: the last live frame),
  /// and of the score screen; close the score screen after `close_after_s` (< 0: by hand).
  std::string screenshot;
  double screenshot_at_s = -1.0;
  /// Window only: start with the bone stress view on (key B toggles it).
  bool stress_view = false;
  std::string score_screenshot;
  double close_after_s = -1.0;
};

/// Exit codes: 0 attempt completed (passed or not), 1 the simulation failed numerically,
/// 2 bad input (scenario, trajectory, database, no device bridge), 3 the attempt was abandoned
/// (window closed before the end; stored as aborted), 4 the module is locked for this trainee.
int run_run(const RunOptions& options, std::ostream& out, std::ostream& err);

}  // namespace acdr
