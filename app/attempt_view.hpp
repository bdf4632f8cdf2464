// A window that shows a live attempt, as the attempt session (app/attempt_session.hpp) drives
// it: the session opens it, runs the attempt on the haptic thread while the view watches, stores
// the attempt, then has the view show the score. The trainee view (ui/trainee_view.hpp)
// implements it, so the session needs no screen library.
#pragma once

#include <string>

#include "app/attempt_runner.hpp"
#include "app/live_attempt.hpp"
#include "engine/devices/input_device.hpp"
#include "engine/world/world.hpp"
#include "scenarios/scenario_model.hpp"

namespace acdr {

class AttemptView {
 public:
  virtual ~AttemptView() = default;

  /// Whether a window can probably be opened (a display exists). When not, the session runs
  /// the attempt headless, or refuses when the view was to provide the input device.
  virtual bool can_open() const = 0;

  /// Opens the window for an attempt of `scenario` in `world`, which nothing steps yet (the
  /// view may read it now). `device` null: the view drives the instrument itself (mouse and
  /// keyboard). `scenario` and `world` must outlive the view's use. Returns false with `error`
  /// set when the window cannot be used.
  virtual bool open(const ScenarioModel& scenario, const World& world, InputDevice* device,
                    std::string* error) = 0;

  /// The device the attempt reads: the one given to open(), or the view's own.
  virtual InputDevice& device() = 0;

  /// Shows `live` (started) until it has ended, on its own or because the trainee finished or
  /// closed the window (the view then asks `live` to stop). Returns after the last frame.
  virtual void watch(LiveAttempt& live) = 0;

  /// Shows the score of the attempt that ended (not abandoned), with `status` (e.g. where it
  /// was stored), until the trainee closes it.
  virtual void show_score(const AttemptRun& run, const std::string& status) = 0;
};

}  // namespace acdr
