// The trainee view: `acdr run SCENARIO` with a display. A GLFW window on the main thread draws
// the scene at ~60 Hz from the views the haptic thread publishes (app/live_attempt.hpp), with a
// Dear ImGui overlay (ui/trainee_hud.hpp): module title and goal, time, force gauge, nucleus
// removed, zone and overload warnings, camera controls; at the end, the score screen. With no
// device the mouse and keyboard drive the instrument (ui/mouse_instrument.hpp,
// docs/trainee-view.md).
#pragma once

#include <functional>
#include <string>

#include "app/attempt_runner.hpp"
#include "app/live_attempt_checkpoints.hpp"
#include "engine/devices/haptic_loop.hpp"
#include "engine/devices/input_device.hpp"
#include "engine/world/world.hpp"
#include "scenarios/scenario_model.hpp"

namespace acdr {

struct TraineeViewOptions {
  int width = 1280;  ///< window size (screen coordinates)
  int height = 800;
  /// Write the window's picture (PNG) here, when the attempt's time first reaches
  /// `screenshot_at_s` (< 0: the last live frame, before the score screen).
  std::string screenshot;
  double screenshot_at_s = -1.0;
  /// Write the score screen's picture (PNG) here, once it is shown.
  std::string score_screenshot;
  /// Close the score screen by itself after this long (s); < 0: when the trainee closes it.
  double close_after_s = -1.0;
  bool vsync = true;
  std::string input_label;  ///< shown in the HUD ("udp:7000", "replay:demo.csv"); mouse: "mouse"
  HapticLoopOptions loop;  ///< rate defaults to the scenario's 1 / dt
  /// Checkpoints of the attempt (LiveAttempt::set_checkpoints): every this many simulated
  /// seconds (0: none), through `checkpoint_sink` on a writer thread.
  double checkpoint_every_s = 0.0;
  CheckpointSink checkpoint_sink;
};

struct TraineeViewOutcome {
  bool ok = false;
  std::string error;  ///< why the window could not be used (no display, no GL 3.3, ...)
  AttemptRun run;
  HapticLoopStats haptics;
  LiveCheckpointStats checkpoints;
};

/// Called on the main thread once the attempt has ended, before the score screen shows (store
/// the attempt here, so that closing the score screen loses nothing). Returns a line for the
/// score screen (e.g. "Stored as attempt 12").
using AttemptFinished = std::function<std::string(const AttemptRun&)>;

/// Runs one attempt in a window. `device` null: the mouse and keyboard drive the instrument.
TraineeViewOutcome run_trainee_view(const ScenarioModel& scenario, World& world,
                                    InputDevice* device, const TraineeViewOptions& options,
                                    const AttemptFinished& on_finished);

/// True when a window can probably be opened (DISPLAY or WAYLAND_DISPLAY set).
bool display_available();

}  // namespace acdr
