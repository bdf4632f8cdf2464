// The attempt loop.
#include "ui/attempt_runner.hpp"

#include <chrono>
#include <cmath>

#include "assessment/metrics.hpp"
#include "assessment/scoring.hpp"
#include "engine/trajectory.hpp"

namespace acdr {

const char* attempt_end_name(AttemptEnd end) {
  switch (end) {
    case AttemptEnd::kInputEnded: return "input ended";
    case AttemptEnd::kTimeLimit: return "time limit";
    case AttemptEnd::kNumericalFailure: return "numerical failure";
    case AttemptEnd::kStopped: return "stopped";
  }
  return "?";
}

AttemptRun run_attempt(const ScenarioModel& scenario, World& world, InputDevice& device,
                       const StepObserver& observer) {
  AttemptRun run;
  const double dt = scenario.world.solver.dt_s;
  const double limit = scenario.time_limit_s;
  if (limit > 0) run.record.frames.reserve(static_cast<std::size_t>(limit / dt) + 16);

  const auto start = std::chrono::steady_clock::now();
  DeviceSample sample;
  sample.pose = scenario.world.instrument_start;
  for (;;) {
    const double t_next = world.time_s() + dt;
    DeviceSample fresh = sample;
    if (device.sample(t_next, fresh)) sample = fresh;
    const Frame& frame = world.step(sample);
    device.render_force(frame.feedback_force_N);
    run.record.frames.push_back(frame);
    world.drain_events(run.record.events);
    if (world.failed()) {
      run.end = AttemptEnd::kNumericalFailure;
      break;
    }
    if (observer && !observer(world, frame)) {
      run.end = AttemptEnd::kStopped;
      break;
    }
    if (sample.end) {
      run.end = AttemptEnd::kInputEnded;
      break;
    }
    if (limit > 0 && world.time_s() >= limit - 0.5 * dt) {
      run.end = AttemptEnd::kTimeLimit;
      break;
    }
  }
  run.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  run.record.events.push_back(
      Event{world.time_s(), EventKind::kAttemptEnd, 0.0, attempt_end_name(run.end)});
  run.record.summary = world.summary();
  run.metrics = compute_metrics(run.record);
  run.score = score_attempt(run.metrics, scenario.rubric);
  run.state_hash = world.state_hash();
  return run;
}

std::unique_ptr<InputDevice> open_input(const std::string& spec, std::string* error) {
  const auto colon = spec.find(':');
  const std::string kind = spec.substr(0, colon);
  const std::string arg = colon == std::string::npos ? "" : spec.substr(colon + 1);
  if (kind == "replay") {
    if (arg.empty()) {
      *error = "--input replay:FILE needs a trajectory file (got '" + spec + "')";
      return nullptr;
    }
    auto trajectory = Trajectory::load_csv(arg, error);
    if (!trajectory) return nullptr;
    return std::make_unique<TrajectoryReplay>(std::move(*trajectory));
  }
  *error = "unknown input '" + spec + "' (expected replay:FILE)";
  return nullptr;
}

}  // namespace acdr
