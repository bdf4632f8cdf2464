// Live attempt on the haptic thread.
#include "ui/live_attempt.hpp"

namespace acdr {
namespace {

HapticLoopOptions with_scenario_rate(HapticLoopOptions options, const ScenarioModel& scenario) {
  if (options.rate_hz <= 0 || options.rate_hz == HapticLoopOptions{}.rate_hz)
    options.rate_hz = 1.0 / scenario.world.solver.dt_s;
  return options;
}

}  // namespace

LiveAttempt::LiveAttempt(const ScenarioModel& scenario, World& world, InputDevice& device,
                         HapticLoopOptions options)
    : world_(world),
      stepper_(scenario, world, device),
      loop_(with_scenario_rate(options, scenario)) {}

LiveAttempt::~LiveAttempt() {
  request_stop();
  loop_.join();
}

void LiveAttempt::start() {
  started_ = true;
  loop_.start([this] { return tick(); });
}

void LiveAttempt::fill(LiveView& view) const {
  capture_world_state(world_, view.state);
  const auto& events = stepper_.record().events;
  // Events only ever grow: append the new ones.
  if (view.events.size() <= events.size())
    view.events.insert(view.events.end(), events.begin() + static_cast<long>(view.events.size()),
                       events.end());
  view.sample = stepper_.last_sample();
  view.ended = stepper_.ended();
  view.end = stepper_.end();
  view.steps = world_.step_count();
}

bool LiveAttempt::tick() {
  if (stop_requested_.load(std::memory_order_acquire))
    stepper_.stop(static_cast<AttemptEnd>(stop_reason_.load(std::memory_order_relaxed)));
  const bool more = stepper_.step();
  if (!more) {
    // The last view is published even if a reader has to be waited for: stepping is over.
    view_.publish([this](LiveView& v) { fill(v); });
    return false;
  }
  if (view_wanted_.load(std::memory_order_relaxed) &&
      view_.try_publish([this](LiveView& v) { fill(v); }))
    view_wanted_.store(false, std::memory_order_relaxed);
  return true;
}

bool LiveAttempt::latest(LiveView& out) {
  const bool changed = view_.read([&](const LiveView& v) { out = v; }, &seen_version_);
  view_wanted_.store(true, std::memory_order_relaxed);
  return changed;
}

AttemptRun LiveAttempt::wait() {
  loop_.join();
  waited_ = true;
  return stepper_.finish(loop_.stats().wall_s);
}

}  // namespace acdr
