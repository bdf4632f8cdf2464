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

enum class AttemptEnd { kInputEnded, kTimeLimit, kNumericalFailure, kStopped };
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

/// Steps `world` with `device` as described above. The world is left in its final state (for
/// a picture of the last frame).
AttemptRun run_attempt(const ScenarioModel& scenario, World& world, InputDevice& device,
                       const StepObserver& observer = {});

/// Opens an input source from its command-line spelling: "replay:FILE.csv".
/// Returns null with `error` set when the spelling or the file is wrong.
std::unique_ptr<InputDevice> open_input(const std::string& spec, std::string* error);

}  // namespace acdr
