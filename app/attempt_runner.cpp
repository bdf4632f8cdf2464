// The attempt loop.
#include "app/attempt_runner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>

#include "assessment/bone_metrics.hpp"
#include "assessment/metrics.hpp"
#include "assessment/scoring.hpp"
#include "engine/devices/trajectory.hpp"
#include "scenarios/scenario_cost.hpp"

namespace acdr {

const char* attempt_end_name(AttemptEnd end) {
  switch (end) {
    case AttemptEnd::kInputEnded: return "input ended";
    case AttemptEnd::kTimeLimit: return "time limit";
    case AttemptEnd::kNumericalFailure: return "numerical failure";
    case AttemptEnd::kStopped: return "stopped";
    case AttemptEnd::kDisconnected: return "device disconnected";
  }
  return "?";
}

AttemptStepper::AttemptStepper(const ScenarioModel& scenario, World& world, InputDevice& device)
    : scenario_(scenario), world_(world), device_(device) {
  const double dt = scenario.world.solver.dt_s;
  const double limit = scenario.time_limit_s;
  // One frame per step; never more than the recording cap (scenarios/scenario_cost.hpp).
  if (limit > 0)
    run_.record.frames.reserve(std::min(static_cast<std::size_t>(limit / dt) + 16, kMaxRecordingFrames));
  run_.record.events.reserve(1024);
  sample_.pose = scenario.world.instrument_start;
  // Set now (it does not change) so checkpoints can compute metrics of the record so far.
  run_.record.summary = world_.summary();
  // The bone's solves run beside the attempt from its first sample on (bone_stress_worker.hpp).
  if (scenario.bone.enabled && world.anatomy() != nullptr) {
    bone_ = std::make_unique<BoneStressWorker>(
        *world.anatomy(), scenario.bone, anatomy_cache_dir(scenario.world.anatomy, "bone"));
    if (limit > 0)
      run_.record.bone_loads.reserve(static_cast<std::size_t>(limit / scenario.bone.sample_period_s) + 16);
  }
}

void AttemptStepper::set_checkpoints(double every_s, CheckpointSink sink) {
  checkpoint_every_s_ = every_s;
  next_checkpoint_s_ = world_.time_s() + every_s;
  checkpoint_sink_ = std::move(sink);
}

bool AttemptStepper::step() {
  if (ended_) return false;
  const double dt = scenario_.world.solver.dt_s;
  const double limit = scenario_.time_limit_s;
  const double t_next = world_.time_s() + dt;
  DeviceSample fresh = sample_;
  if (device_.sample(t_next, fresh)) sample_ = fresh;
  const Frame& frame = world_.step(sample_);
  device_.render_force(frame.feedback_force_N);
  run_.record.frames.push_back(frame);
  world_.drain_events(run_.record.events);
  if (const BoneLoadSample* loads = world_.bone_loads(); loads && bone_) {
    BoneLoadRecord& r = run_.record.bone_loads.emplace_back();
    r.t_s = loads->t_s;
    r.points.assign(loads->points.begin(), loads->points.begin() + loads->count);
    bone_->push(r);
  }
  if (world_.failed()) {
    stop(AttemptEnd::kNumericalFailure);
  } else if (sample_.disconnected) {
    run_.record.events.push_back(Event{world_.time_s(), EventKind::kDeviceDisconnected,
                                       sample_.silence_s, "no device packet within the timeout"});
    stop(AttemptEnd::kDisconnected);
  } else if (sample_.end) {
    stop(AttemptEnd::kInputEnded);
  } else if ((limit > 0 && world_.time_s() >= limit - 0.5 * dt) ||
             run_.record.frames.size() >= kMaxRecordingFrames) {
    // Without a time limit, the recording cap is the limit (a validated scenario's own limit
    // is within it).
    stop(AttemptEnd::kTimeLimit);
  }
  // Half a step of slack so a checkpoint lands on the step that reaches its time.
  if (checkpoint_sink_ && checkpoint_every_s_ > 0 && !ended_ &&
      world_.time_s() >= next_checkpoint_s_ - 0.5 * dt) {
    if (checkpoint_sink_(CheckpointView{run_.record, checkpointed_frames_, checkpointed_events_,
                                        world_.time_s(), checkpointed_bone_samples_})) {
      checkpointed_frames_ = run_.record.frames.size();
      checkpointed_events_ = run_.record.events.size();
      checkpointed_bone_samples_ = run_.record.bone_loads.size();
    }
    next_checkpoint_s_ += checkpoint_every_s_;
  }
  return !ended_;
}

void AttemptStepper::stop(AttemptEnd why) {
  if (ended_) return;
  ended_ = true;
  end_ = why;
}

AttemptRun AttemptStepper::finish(double wall_s) {
  run_.end = end_;
  run_.wall_s = wall_s;
  run_.record.events.push_back(
      Event{world_.time_s(), EventKind::kAttemptEnd, 0.0, attempt_end_name(run_.end)});
  run_.record.summary = world_.summary();
  // Where the removed material lies at the end, for the lump metrics.
  auto& removed = run_.record.removed_positions.emplace();
  if (const Nucleus* nucleus = world_.nucleus()) {
    const auto positions = nucleus->positions();
    for (std::size_t i = 0; i < positions.size(); ++i)
      if (world_.is_removed(i)) removed.push_back(positions[i].cast<float>());
  }
  run_.metrics = compute_metrics(run_.record);
  if (bone_) {
    run_.bone_modelled = true;
    BoneStressSummary bone;
    if (bone_->finish(&bone, &run_.bone_stats, &run_.bone_error)) add_bone_metrics(bone, run_.metrics);
    bone_.reset();
  }
  run_.score = score_attempt(run_.metrics, scenario_.rubric);
  run_.state_hash = world_.state_hash();
  device_.finish(attempt_end_name(run_.end));
  return std::move(run_);
}

AttemptRun run_attempt(const ScenarioModel& scenario, World& world, InputDevice& device,
                       const StepObserver& observer) {
  return run_attempt(scenario, world, device, observer, 0.0, {});
}

AttemptRun run_attempt(const ScenarioModel& scenario, World& world, InputDevice& device,
                       const StepObserver& observer, double checkpoint_every_s,
                       CheckpointSink checkpoint_sink) {
  AttemptStepper stepper(scenario, world, device);
  if (checkpoint_sink) stepper.set_checkpoints(checkpoint_every_s, std::move(checkpoint_sink));
  const auto start = std::chrono::steady_clock::now();
  for (;;) {
    const bool more = stepper.step();
    if (observer && !observer(world, world.last_frame()) && more) {
      stepper.stop(AttemptEnd::kStopped);
      break;
    }
    if (!more) break;
  }
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stepper.finish(wall);
}

int scene_instrument_count(const WorldConfig& world) {
  return world.instruments.empty() ? 1 : static_cast<int>(world.instruments.size());
}

std::unique_ptr<InputDevice> open_input(const std::string& spec, std::string* error,
                                        double udp_disconnect_timeout_s, int scene_instruments) {
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
    if (scene_instruments > 0 && trajectory->max_instrument() >= scene_instruments) {
      *error = arg + ": the instrument column asks for instrument " +
               std::to_string(trajectory->max_instrument()) + ", expected 0 to " +
               std::to_string(scene_instruments - 1) + " (the scene has " +
               std::to_string(scene_instruments) + " instrument" +
               (scene_instruments == 1 ? "" : "s") + ", world.instruments)";
      return nullptr;
    }
    return std::make_unique<TrajectoryReplay>(std::move(*trajectory));
  }
  if (kind == "udp") {
    char* end = nullptr;
    const long port = std::strtol(arg.c_str(), &end, 10);
    if (arg.empty() || *end != '\0' || port < 1 || port > 65535) {
      *error = "--input udp:PORT needs a port number 1-65535 (got '" + spec + "')";
      return nullptr;
    }
    UdpDeviceOptions options;
    options.port = static_cast<int>(port);
    options.disconnect_timeout_s = udp_disconnect_timeout_s;
    return UdpDevice::open(options, error);
  }
  if (kind == "mouse") {
    *error = "--input mouse needs a window (drop --headless, and run with a display)";
    return nullptr;
  }
  *error = "unknown input '" + spec + "' (expected replay:FILE, udp:PORT or mouse)";
  return nullptr;
}

}  // namespace acdr
