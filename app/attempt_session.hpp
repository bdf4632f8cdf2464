// One attempt from its scenario file to its stored record, as one library call. In order:
// load the scenario; open the input device (a replay or a haptic bridge; the mouse belongs to
// the view); open the record, register the module and every module of its curriculum (the
// scenario files beside it, or in a given folder), check the progression
// gate and begin the attempt (its row exists from the start, so a crash leaves a trace); run
// it, headless as fast as it steps, or live on the haptic thread (a bridge, or a window the
// session drives through AttemptView), with periodic checkpoints; store it, completed or
// aborted; and hand back what happened for the caller to show. Nothing here draws or prints a
// result.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>

#include "app/attempt_runner.hpp"
#include "app/attempt_view.hpp"
#include "app/lrs_delivery.hpp"
#include "app/live_attempt_checkpoints.hpp"
#include "engine/devices/haptic_loop.hpp"
#include "engine/devices/udp_device.hpp"
#include "engine/world/world.hpp"
#include "scenarios/scenario_model.hpp"

namespace acdr {

struct SessionOptions {
  std::string scenario;  ///< scenario file (JSON)
  /// replay:FILE (a recorded trajectory), udp:PORT (a haptic bridge on loopback, see
  /// docs/haptic-bridge.md) or mouse (mouse and keyboard; the view's own device).
  std::string input = "replay:";
  std::optional<std::string> trainee;  ///< none: a practice attempt (never locked)
  bool override_lock = false;     ///< an instructor lets the trainee take a locked module
  std::string override_by;        ///< who decided (required with override_lock)
  std::string override_reason;
  std::string db;                 ///< empty: default_database_path()
  /// The folder whose scenario files make up the scenario's curriculum (every file there with
  /// the same `curriculum` is registered before the gate is checked, so the lock holds from
  /// the first attempt). Empty: the scenario file's own folder (for a bundled module, the
  /// bundled set in scenarios/modules/).
  std::string curriculum_dir;
  std::string record;             ///< also write the recording to this file, when set
  /// udp: how long to wait for the bridge's first packet, and the disconnect timeout (s).
  double device_timeout_s = 5.0;
  /// Run the haptic loop with real-time priority when the OS grants it (haptics.realtime).
  bool realtime = false;
  /// Store a checkpoint (recording so far, events, metrics) every this many simulated seconds,
  /// so a killed run leaves an aborted attempt with what was recorded (0: never). A headless
  /// replay writes it on its stepping thread; a live attempt (window, bridge) on a writer
  /// thread of its own, so the physics loop never waits for it.
  double checkpoint_every_s = 5.0;
  /// When the final record cannot be written (the database locked by another program, the
  /// disk full), keep trying for this long (s) before keeping the result in a side file next
  /// to the database (db/outcome_side_file.hpp), stored there at the next start.
  double store_patience_s = 10.0;
  /// No progress notes (waiting for the bridge); warnings still come.
  bool quiet = false;
  /// The LRS configuration file (net/lrs_config.hpp); none: $ACDR_LRS_CONFIG or the XDG
  /// default, and the environment. Its IRI base goes into the queued statements; with
  /// send_after_attempt the outbox is sent once the attempt is stored.
  std::optional<std::string> lrs_config;
};

/// How the session ended.
enum class SessionEnd {
  kCompleted,         ///< the attempt ran to its end and was stored (passed or not)
  kNumericalFailure,  ///< the simulation failed numerically; stored as completed
  kAbandoned,         ///< stopped before its end by the trainee; stored as aborted
  kBadInput,          ///< scenario, input, record, bridge, window or store refused (`error`)
  kLocked,            ///< the module is locked for this trainee (`error` says why)
  /// The attempt ran to its end but its record could not be written (`error` says why); the
  /// result waits in `unsaved_file` (when that could be written) for the next start. Also
  /// when only the `record` file could not be written: the attempt itself is stored.
  kRecordNotWritten,
};

/// How a live device drove the attempt: the haptic loop's achieved rate and the link's figures
/// (the UDP bridge's, when there was one).
struct HapticsReport {
  HapticLoopStats loop;     ///< the device loop (the only loop for a replay)
  bool decoupled = false;   ///< the physics had a loop of its own (a live device)
  HapticLoopStats physics;  ///< that loop, when decoupled
  std::int64_t device_ticks_clamped = 0;  ///< device-loop forces clamped to the maximum
  std::int64_t device_ticks_zeroed = 0;   ///< device-loop forces zeroed (stale/NaN/jump)
  bool has_link = false;
  UdpDeviceStats link;
};

/// What the checkpoints of a live attempt cost (its writer thread's figures).
struct CheckpointReport {
  double every_s = 0.0;
  LiveCheckpointStats stats;
};

struct SessionResult {
  SessionEnd end = SessionEnd::kBadInput;
  /// kBadInput, kLocked: what is wrong, one or more lines without the last line break.
  std::string error;
  std::shared_ptr<const ScenarioModel> scenario;  ///< set once loaded
  std::unique_ptr<World> world;  ///< the final state, once the attempt ran
  AttemptRun run;
  std::int64_t attempt_id = 0;
  std::string db_path;
  std::string stored_as;  ///< "completed", "aborted", or "not written" (kRecordNotWritten)
  std::string unsaved_file;  ///< kRecordNotWritten: the side file keeping the result
  std::optional<HapticsReport> haptics;         ///< a live attempt (window, bridge)
  std::optional<CheckpointReport> checkpoints;  ///< a live attempt's checkpoint writer
  std::optional<DeliveryReport> delivery;  ///< the outbox sent after the attempt, when asked

  /// The attempt ran and was stored.
  bool ran() const { return end != SessionEnd::kBadInput && end != SessionEnd::kLocked; }
};

/// Runs one attempt as described above. `view` null, or one that cannot open: headless (a
/// note on `notes` in the latter case). Notes and warnings (no display, waiting for the
/// bridge, checkpoints refused) go to `notes` as they happen; the result says the rest.
SessionResult run_attempt_session(const SessionOptions& options, AttemptView* view,
                                  std::ostream& notes);

}  // namespace acdr
