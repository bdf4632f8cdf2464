// Runs one attempt: a World built from a scenario, stepped at its fixed rate by an input
// device until the input ends, the time limit passes, or the simulation fails. Produces the
// record, the metrics and the score; storing and drawing are the caller's business.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "assessment/attempt_recording.hpp"
#include "assessment/attempt_result.hpp"
#include "engine/input_device.hpp"
#include "engine/world.hpp"
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
};

/// Called after every step; return false to stop the attempt (e.g. a window was closed).
using StepObserver = std::function<bool(const World&, const Frame&)>;

/// The attempt one step at a time, for whoever drives the clock: run_attempt's tight loop, or
/// the haptic thread of a live attempt (ui/live_attempt.hpp). Each step reads the device,
/// steps the world, sends the force back, records the frame and events, and checks the ends.
class AttemptStepper {
 public:
  /// `world` and `device` must outlive the stepper.
  AttemptStepper(const ScenarioModel& scenario, World& world, InputDevice& device);

  /// One fixed step; returns false once the attempt has ended (then end() says why).
  bool step();
  /// Ends the attempt from outside (window closed, Escape): no more steps.
  void stop(AttemptEnd why = AttemptEnd::kStopped);
  bool ended() const { return ended_; }
  AttemptEnd end() const { return end_; }
  const AttemptRecording& record() const { return run_.record; }
  const DeviceSample& last_sample() const { return sample_; }

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
};

/// Steps `world` with `device` as described above. The world is left in its final state (for
/// a picture of the last frame).
AttemptRun run_attempt(const ScenarioModel& scenario, World& world, InputDevice& device,
                       const StepObserver& observer = {});

/// Opens an input source from its command-line spelling: "replay:FILE.csv", or
/// "udp:PORT" for a haptic bridge on loopback (engine/udp_device.hpp). ("mouse" needs a window
/// and is opened by the trainee view.) Returns null with `error` set when the spelling or the
/// file is wrong or the port cannot be bound.
std::unique_ptr<InputDevice> open_input(const std::string& spec, std::string* error);

}  // namespace acdr
