// `acdr run SCENARIO`: one attempt, scored, stored, optionally pictured.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>

namespace acdr {

struct RunOptions {
  std::string scenario;
  /// replay:FILE (a recorded trajectory), udp:PORT (a haptic bridge on loopback, see
  /// docs/haptic-bridge.md) or mouse (mouse and keyboard; needs the window).
  std::string input = "replay:";
  std::optional<std::string> trainee;  ///< none: a practice attempt
  bool override_lock = false;     ///< an instructor lets the trainee take a locked module
  std::string override_by;        ///< who decided (required with override_lock)
  std::string override_reason;
  std::string db;                 ///< empty: default_database_path()
  std::string png;                ///< final frame picture, when set
  std::string record;             ///< also write the recording to this file, when set
  bool json = false;
  /// No window. Without this flag a window opens when a display exists (else the run is
  /// headless, with a note on stderr).
  bool headless = false;
  int png_width = 1280;
  int png_height = 800;
  /// udp: how long to wait for the bridge's first packet, and the disconnect timeout (s).
  double device_timeout_s = 5.0;
  /// Window only: picture of the window (PNG) at `screenshot_at_s` (< 0: the last live frame),
  /// and of the score screen; close the score screen after `close_after_s` (< 0: by hand).
  std::string screenshot;
  double screenshot_at_s = -1.0;
  std::string score_screenshot;
  double close_after_s = -1.0;
  /// Run the haptic loop with real-time priority when the OS grants it (haptics.realtime).
  bool realtime = false;
  /// Store a checkpoint (recording so far, events, metrics) every this many simulated seconds,
  /// so a killed run leaves an aborted attempt with what was recorded (0: never). A headless
  /// replay writes it on its stepping thread; a live attempt (window, bridge) on a writer
  /// thread of its own, so the physics loop never waits for it.
  double checkpoint_every_s = 5.0;
};

/// Exit codes: 0 attempt completed (passed or not), 1 the simulation failed numerically,
/// 2 bad input (scenario, trajectory, database, no device bridge), 3 the attempt was abandoned
/// (window closed before the end; stored as aborted), 4 the module is locked for this trainee.
int run_run(const RunOptions& options, std::ostream& out, std::ostream& err);

}  // namespace acdr
