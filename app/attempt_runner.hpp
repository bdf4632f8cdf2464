// Runs one attempt: a World built from a scenario, stepped at its fixed rate by an input
// device until the input ends, the time limit passes, or the simulation fails. Produces the
// record, the metrics and the score; storing and drawing are the caller's business.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "assessment/attempt_recording.hpp"
#include "app/bone_stress_worker.hpp"
#include "assessment/attempt_result.hpp"
#include "engine/devices/input_device.hpp"
#include "engine/devices/udp_device.hpp"
#include "engine/world/world.hpp"
#include "scenarios/scenario_model.hpp"

namespace acdr {

enum class AttemptEnd { kInputEnded, kTimeLimit, kNumericalFailure, kStopped, kDisconnected };
const char* attempt_end_name(AttemptEnd end);

struct AttemptRun {
  AttemptRecording record;
  Metrics metrics;
  ScoreResult score;
  AttemptEnd end = AttemptEnd::kInputEnded;
  double wall_s = 0.0;           ///< wall-clock time of the stepping loop
  std::uint64_t state_hash = 0;  ///< World::state_hash() at the end
  /// The bone model (scenario's anatomy.bone): its solver thread's costs, and why it could
  /// not be built ("" when fine; the bone metrics are then missing).
  bool bone_modelled = false;
  BoneWorkerStats bone_stats;
  std::string bone_error;
};

/// Called after every step; return false to stop the attempt (e.g. a window was closed).
using StepObserver = std::function<bool(const World&, const Frame&)>;

/// What a periodic checkpoint sees: the record so far (summary set) and where its new part
/// starts. Valid only during the call.
struct CheckpointView {
  const AttemptRecording& record;
  std::size_t first_new_frame = 0;  ///< frames before this were in earlier checkpoints
  std::size_t first_new_event = 0;  ///< the same for events
  double t_s = 0.0;                 ///< simulated time so far (s)
  std::size_t first_new_bone_sample = 0;  ///< the same for the bone's load samples
};
/// Saves a checkpoint (e.g. db append_checkpoint); runs on the stepping thread, so it should
/// cost milliseconds, and only every few seconds of simulated time. Returns whether it was
/// saved; when not, the next call gets this call's new part as well.
using CheckpointSink = std::function<bool(const CheckpointView&)>;

/// The attempt one step at a time, for whoever drives the clock: run_attempt's tight loop, or
/// the haptic thread of a live attempt (app/live_attempt.hpp). Each step reads the device,
/// steps the world, sends the force back, records the frame and events, and checks the ends.
class AttemptStepper {
 public:
  /// `world` and `device` must outlive the stepper.
  AttemptStepper(const ScenarioModel& scenario, World& world, InputDevice& device);

  /// One fixed step; returns false once the attempt has ended (then end() says why).
  bool step();
  /// Calls `sink` after the step that reaches each multiple of `every_s` of simulated time
  /// (every_s > 0), with what was recorded since the previous call. Set before the first step.
  void set_checkpoints(double every_s, CheckpointSink sink);

  /// Ends the attempt from outside (window closed, Escape): no more steps.
  void stop(AttemptEnd why = AttemptEnd::kStopped);
  bool ended() const { return ended_; }
  AttemptEnd end() const { return end_; }
  const AttemptRecording& record() const { return run_.record; }
  const DeviceSample& last_sample() const { return sample_; }
  /// The bone's solver thread (null when the scenario does not model the bone).
  BoneStressWorker* bone_worker() { return bone_.get(); }

  /// Closes the record (attempt-end event, metrics, score), tells the device, and hands the
  /// run over. Call once, after the last step; `wall_s` is the stepping's wall time.
  AttemptRun finish(double wall_s);

 private:
  const ScenarioModel& scenario_;
  World& world_;
  InputDevice& device_;
  AttemptRun run_;
  DeviceSample sample_;
  bool ended_ = false;
  AttemptEnd end_ = AttemptEnd::kInputEnded;
  double checkpoint_every_s_ = 0.0;
  double next_checkpoint_s_ = 0.0;
  std::size_t checkpointed_frames_ = 0, checkpointed_events_ = 0, checkpointed_bone_samples_ = 0;
  CheckpointSink checkpoint_sink_;
  std::unique_ptr<BoneStressWorker> bone_;
};

/// Steps `world` with `device` as described above. The world is left in its final state (for
/// a picture of the last frame).
AttemptRun run_attempt(const ScenarioModel& scenario, World& world, InputDevice& device,
                       const StepObserver& observer = {});
/// The same with periodic checkpoints (AttemptStepper::set_checkpoints).
AttemptRun run_attempt(const ScenarioModel& scenario, World& world, InputDevice& device,
                       const StepObserver& observer, double checkpoint_every_s,
                       CheckpointSink checkpoint_sink);

/// Opens an input source from its command-line spelling: "replay:FILE.csv", or
/// "udp:PORT" for a haptic bridge on loopback (engine/devices/udp_device.hpp), which ends the
/// attempt as disconnected after `udp_disconnect_timeout_s` without a packet. ("mouse" needs a
/// window and is opened by the view.) Returns null with `error` set when the spelling or the
/// file is wrong or the port cannot be bound, or when a replay's instrument column asks for an
/// instrument beyond the scene's `scene_instruments` (when given, > 0).
std::unique_ptr<InputDevice> open_input(
    const std::string& spec, std::string* error,
    double udp_disconnect_timeout_s = UdpDeviceOptions{}.disconnect_timeout_s,
    int scene_instruments = 0);

/// The number of instruments a scene has on its tray (WorldConfig::instruments, else 1).
int scene_instrument_count(const WorldConfig& world);

}  // namespace acdr
