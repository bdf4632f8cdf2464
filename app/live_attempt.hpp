// An attempt stepped live at the scenario's rate, paced by the clock, while other threads
// watch it. With a live device (a UDP bridge, the mouse) two threads run: the device loop at
// 1 kHz (poses in, forces out through engine/devices/haptic_local_model.hpp) and the physics loop at
// the scenario's rate, which falls behind real time honestly (reported) when a step costs
// more than its period, without slowing the device loop. A replay steps on one thread (the
// device is the recording). Watchers: the trainee view draws the newest
// published view at ~60 Hz, and a headless run just waits. The haptic thread publishes a view
// only when one has been asked for, and only if the reader is not copying the previous one
// at that moment (a try-lock), so rendering never blocks physics. Checkpoints (optional) are
// written on a thread of their own (app/live_attempt_checkpoints.hpp): the physics thread only
// stages each frame and hands the staged part over at each checkpoint time, never waiting.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <vector>

#include "app/attempt_runner.hpp"
#include "app/live_attempt_checkpoints.hpp"
#include "app/world_state.hpp"
#include "engine/core/latest_value.hpp"
#include "engine/devices/haptic_local_model.hpp"
#include "engine/devices/haptic_loop.hpp"

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

  /// Saves a checkpoint every `every_s` of simulated time (> 0; else nothing is done) through
  /// `sink`, called on a writer thread of its own with what was recorded since the previous
  /// saved checkpoint (the same contract as AttemptStepper::set_checkpoints). When the writer
  /// is still busy at a checkpoint time, that part goes with the next one. wait() lets the
  /// writer write everything handed over (and, for an attempt stopped before its end, the
  /// rest as well) before it closes the attempt, so the sink's store is free again when wait()
  /// returns. Call before start().
  void set_checkpoints(double every_s, CheckpointSink sink);

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

  /// The device loop's achieved rate and periods (live or final); the physics loop's when
  /// both are one (replay).
  HapticLoopStats haptic_stats() const { return decoupled_ ? device_loop_->stats() : loop_.stats(); }
  /// The physics loop's rate and step times (live or final).
  HapticLoopStats physics_stats() const { return loop_.stats(); }
  /// What the checkpoints cost (exact after wait(); zeros without checkpoints).
  LiveCheckpointStats checkpoint_stats() const {
    return checkpoints_ ? checkpoints_->stats() : LiveCheckpointStats{};
  }
  /// True when the device has its own loop (a live device).
  bool decoupled() const { return decoupled_; }
  /// The simulated time the physics has reached (s), readable from any thread: a device that
  /// counts its motion in simulated seconds (the mouse) moves the same in slow motion.
  double simulated_time_s() const { return simulated_s_.load(std::memory_order_relaxed); }
  /// The bone's solver thread of this attempt (null when the scene does not model the bone).
  BoneStressWorker* bone_worker() { return stepper_.bone_worker(); }
  /// Device ticks whose force was clamped, or zeroed for stale, non-finite or jumped input.
  std::int64_t device_clamped_ticks() const { return clamped_ticks_.load(); }
  std::int64_t device_zeroed_ticks() const { return zeroed_ticks_.load(); }

 private:
  /// The physics side's view of the device: the newest sample the device loop handed over,
  /// and the force each step computes handed back to it.
  class DeviceLink final : public InputDevice {
   public:
    explicit DeviceLink(InputDevice& device) : device_(device) {}
    bool sample(double t_s, DeviceSample& out) override;
    void render_force(const Vec3& force_N) override;
    void finish(const char* reason) override { device_.finish(reason); }

    LatestValue<DeviceSample> samples;  ///< written by the device loop
    LatestValue<PhysicsForce> forces;   ///< written by the physics loop
    /// A faulty sample waits for the physics to read it (set by the device loop).
    std::atomic<bool> fault_pending{false};

   private:
    InputDevice& device_;
    std::uint64_t seen_ = 0;
    Vec3 consumed_position_ = Vec3::Zero();
  };

  bool tick();
  bool device_tick();
  void fill(LiveView& view) const;

  const World& world_;
  InputDevice& device_;
  const bool decoupled_;
  std::unique_ptr<DeviceLink> link_;  ///< decoupled only
  AttemptStepper stepper_;
  std::unique_ptr<LiveAttemptCheckpoints> checkpoints_;  ///< when set_checkpoints was called
  HapticLoop loop_;  ///< the physics loop (and the device's, when not decoupled)
  std::unique_ptr<HapticLoop> device_loop_;
  std::unique_ptr<HapticLocalModel> local_;
  DeviceSample device_sample_;  ///< device loop only
  std::chrono::steady_clock::time_point device_start_;
  std::atomic<std::int64_t> clamped_ticks_{0};
  std::atomic<std::int64_t> zeroed_ticks_{0};
  std::atomic<double> simulated_s_{0.0};  ///< world time after the newest step
  LatestValue<LiveView> view_;
  std::atomic<bool> view_wanted_{true};
  std::atomic<bool> stop_requested_{false};
  std::atomic<int> stop_reason_{static_cast<int>(AttemptEnd::kStopped)};
  std::uint64_t seen_version_ = 0;
  bool started_ = false;
  bool waited_ = false;
};

}  // namespace acdr
