// An attempt stepped live on the haptic thread (engine/haptic_loop.hpp) at the scenario's
// rate, paced by the clock, while other threads watch it: the trainee view draws the newest
// published view at ~60 Hz, and a headless run just waits. The haptic thread publishes a view
// only when one has been asked for, and only if the reader is not copying the previous one
// at that moment (a try-lock), so rendering never blocks physics.
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include "engine/haptic_loop.hpp"
#include "engine/latest_value.hpp"
#include "ui/attempt_runner.hpp"
#include "ui/scene_snapshot.hpp"

namespace acdr {

/// What a watcher sees of a live attempt.
struct LiveView {
  WorldState state;              ///< instrument, particles, the last frame
  std::vector<Event> events;     ///< every event so far, in time order
  DeviceSample sample;           ///< the device sample in force (stale, buttons, ...)
  bool ended = false;
  AttemptEnd end = AttemptEnd::kInputEnded;
  std::int64_t steps = 0;
};

class LiveAttempt {
 public:
  /// `scenario`, `world` and `device` must outlive this object. The loop's rate defaults to
  /// the scenario's step rate (1 / dt).
  LiveAttempt(const ScenarioModel& scenario, World& world, InputDevice& device,
              HapticLoopOptions options = {});
  /// Stops the attempt if it still runs and waits for the thread.
  ~LiveAttempt();
  LiveAttempt(const LiveAttempt&) = delete;
  LiveAttempt& operator=(const LiveAttempt&) = delete;

  /// Starts the haptic thread. Call once.
  void start();
  /// True once the attempt has ended (input ended, time limit, failure, disconnect, stop).
  bool finished() const { return loop_.finished(); }
  /// Ends the attempt at the next step (any thread): kStopped (abandoned, e.g. the window
  /// closed) or kInputEnded (the trainee said "done").
  void request_stop(AttemptEnd why = AttemptEnd::kStopped) {
    stop_reason_.store(static_cast<int>(why), std::memory_order_relaxed);
    stop_requested_.store(true, std::memory_order_release);
  }

  /// Copies the newest published view into `out` when it is newer than the last one this
  /// caller saw, and asks the haptic thread for the next. Returns whether `out` changed.
  bool latest(LiveView& out);

  /// Waits for the attempt to end and closes it (metrics, score). Call once.
  AttemptRun wait();

  /// The loop's achieved rate and periods (live or final).
  HapticLoopStats haptic_stats() const { return loop_.stats(); }

 private:
  bool tick();
  void fill(LiveView& view) const;

  const World& world_;
  AttemptStepper stepper_;
  HapticLoop loop_;
  LatestValue<LiveView> view_;
  std::atomic<bool> view_wanted_{true};
  std::atomic<bool> stop_requested_{false};
  std::atomic<int> stop_reason_{static_cast<int>(AttemptEnd::kStopped)};
  std::uint64_t seen_version_ = 0;
  bool started_ = false;
  bool waited_ = false;
};

}  // namespace acdr
