// Live attempt on the haptic thread.
#include "app/live_attempt.hpp"

namespace acdr {
namespace {

HapticLoopOptions with_scenario_rate(HapticLoopOptions options, const ScenarioModel& scenario) {
  if (options.rate_hz <= 0 || options.rate_hz == HapticLoopOptions{}.rate_hz)
    options.rate_hz = 1.0 / scenario.world.solver.dt_s;
  return options;
}

}  // namespace

bool LiveAttempt::DeviceLink::sample(double, DeviceSample& out) {
  const bool fresh = samples.read([&](const DeviceSample& s) { out = s; }, &seen_);
  if (fresh) {
    consumed_position_ = out.pose.position;
    // The faulty pose itself has now reached the physics (its guard records it).
    if (!out.pose.position.allFinite() || !out.pose.orientation.coeffs().allFinite())
      fault_pending.store(false, std::memory_order_release);
  }
  return fresh;
}

void LiveAttempt::DeviceLink::render_force(const Vec3& force_N) {
  // After the last step the reader may be waited for; during the attempt a busy lock only
  // skips one hand-over.
  forces.try_publish([&](PhysicsForce& f) {
    f.force_N = force_N;
    f.device_position_m = consumed_position_;
    f.valid = true;
  });
}

LiveAttempt::LiveAttempt(const ScenarioModel& scenario, World& world, InputDevice& device,
                         HapticLoopOptions options)
    : world_(world),
      device_(device),
      decoupled_(device.live()),
      link_(decoupled_ ? std::make_unique<DeviceLink>(device) : nullptr),
      stepper_(scenario, world, decoupled_ ? static_cast<InputDevice&>(*link_) : device),
      loop_(with_scenario_rate(options, scenario)) {
  if (decoupled_) {
    // The device loop keeps the requested rate (1 kHz by default) whatever the scene's step;
    // the physics loop is paced at the scenario's rate.
    HapticLoopOptions device_options = options;
    if (device_options.rate_hz <= 0) device_options.rate_hz = HapticLoopOptions{}.rate_hz;
    device_loop_ = std::make_unique<HapticLoop>(device_options);
    local_ = std::make_unique<HapticLocalModel>(scenario.world.device,
                                                scenario.world.coupling.stiffness_N_m,
                                                1.0 / device_options.rate_hz);
    device_sample_.pose = scenario.world.instrument_start;
  }
}

LiveAttempt::~LiveAttempt() {
  request_stop();
  loop_.join();
  if (device_loop_) {
    device_loop_->request_stop();
    device_loop_->join();
  }
  if (checkpoints_) checkpoints_->finish(false);
}

void LiveAttempt::set_checkpoints(double every_s, CheckpointSink sink) {
  if (started_ || !(every_s > 0) || !sink) return;
  const double dt = world_.config().solver.dt_s;
  checkpoints_ = std::make_unique<LiveAttemptCheckpoints>(
      std::move(sink), stepper_.record().summary,
      static_cast<std::size_t>(every_s / dt) + 1);
  // The stepper keeps the schedule (the step that reaches each multiple of every_s); at those
  // steps the physics thread only stages the new frame and hands the staged part over.
  stepper_.set_checkpoints(every_s, [this](const CheckpointView& view) {
    checkpoints_->stage(view.record);
    return checkpoints_->hand_over(view.t_s);
  });
}

void LiveAttempt::start() {
  started_ = true;
  if (checkpoints_) checkpoints_->start();
  if (decoupled_) {
    device_start_ = std::chrono::steady_clock::now();
    device_loop_->start([this] { return device_tick(); });
  }
  loop_.start([this] { return tick(); });
}

// Device loop: the newest pose to the physics, the local model's force to the device.
bool LiveAttempt::device_tick() {
  const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                                 device_start_).count();
  if (device_.sample(t, device_sample_)) {
    // Most samples may be skipped when the physics is busy (a newer one follows), but a
    // non-finite pose lasts one packet and an end or a disconnect must arrive: those are
    // handed over with a wait. Newer poses then wait until the physics has read the faulty
    // one, so its guard rejects and records it.
    const bool fault = !device_sample_.pose.position.allFinite() ||
                       !device_sample_.pose.orientation.coeffs().allFinite();
    if (fault) link_->fault_pending.store(true, std::memory_order_release);
    if (fault || device_sample_.end || device_sample_.disconnected)
      link_->samples.publish([&](DeviceSample& s) { s = device_sample_; });
    else if (!link_->fault_pending.load(std::memory_order_acquire))
      link_->samples.try_publish([&](DeviceSample& s) { s = device_sample_; });
  }
  PhysicsForce physics;
  link_->forces.read([&](const PhysicsForce& f) { physics = f; });
  const LocalForce f = local_->force(physics, device_sample_.pose.position, device_sample_.stale);
  device_.render_force(f.force_N);
  if (f.clamped) clamped_ticks_.fetch_add(1, std::memory_order_relaxed);
  if (f.zeroed) zeroed_ticks_.fetch_add(1, std::memory_order_relaxed);
  if (loop_.finished()) {
    device_.render_force(Vec3::Zero());
    return false;
  }
  return true;
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
  // The device loop ends only after this one, unless its step threw: then no pose will come.
  if (device_loop_ && device_loop_->finished()) stepper_.stop(AttemptEnd::kStopped);
  const bool more = stepper_.step();
  simulated_s_.store(world_.time_s(), std::memory_order_relaxed);
  // Each step's frame (a few hundred bytes) to the checkpoint staging buffer.
  if (checkpoints_) checkpoints_->stage(stepper_.record());
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
  if (device_loop_) device_loop_->join();
  // Before the attempt is closed and stored: the writer writes what it was given and ends.
  // An attempt abandoned before its end keeps only what was checkpointed, so it gets the
  // rest too; a finished attempt is stored whole right after this.
  const bool failed = loop_.failed() || (device_loop_ && device_loop_->failed());
  if (checkpoints_) checkpoints_->finish(failed || stepper_.end() == AttemptEnd::kStopped);
  waited_ = true;
  // A loop whose step threw (out of memory) ended the attempt there: its exception goes on
  // from here, after the checkpoints kept what was recorded.
  loop_.rethrow_failure();
  if (device_loop_) device_loop_->rethrow_failure();
  return stepper_.finish(loop_.stats().wall_s);
}

}  // namespace acdr
