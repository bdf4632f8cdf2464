// Benchmark runs of a World along a trajectory.
#include "bench/scene_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>

namespace acdr {

double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

Pose pose_on_path(const Pose& start, const std::vector<Pose>& path, double sample_s, double t) {
  if (path.empty()) return start;
  const double u = t / sample_s;
  const double k_f = std::floor(u);
  const auto k = static_cast<long>(k_f);
  if (k >= static_cast<long>(path.size())) return path.back();
  const Pose& a = k <= 0 ? start : path[k - 1];
  const Pose& b = path[std::max<long>(k, 0)];
  const double w = std::clamp(u - k_f, 0.0, 1.0);
  Pose p;
  p.position = (1.0 - w) * a.position + w * b.position;
  p.orientation = a.orientation.slerp(w, b.orientation);
  return p;
}

WorldConfig apply_settings(const WorldConfig& base, const RunSettings& s) {
  WorldConfig c = base;
  if (s.dt_s > 0.0) c.solver.dt_s = s.dt_s;
  if (s.max_iterations > 0) c.solver.max_iterations = s.max_iterations;
  if (s.tolerance > 0.0) c.solver.tolerance = s.tolerance;
  if (s.spacing_m > 0.0) c.nucleus.spacing_m = s.spacing_m;
  if (s.sleep >= 0) c.solver.sleep_enabled = s.sleep != 0;
  return c;
}

RunTrace run_scene(const WorldConfig& config_in, const Trajectory& trajectory,
                   const RunWindow& window, const std::function<void(double)>& progress,
                   const RunObserver& observer) {
  using Clock = std::chrono::steady_clock;
  RunTrace out;
  WorldConfig config = config_in;
  const double t0 = window.start_s;
  config.instrument_start = trajectory.at(t0);
  World world(config);
  const double dt = config.solver.dt_s;
  const double duration =
      window.duration_s > 0.0 ? window.duration_s : trajectory.duration_s() - t0;
  const auto steps = static_cast<std::int64_t>(std::llround(duration / dt));
  const auto windows = static_cast<std::size_t>(std::floor(duration / window.sample_s + 1e-9));
  out.t_s.reserve(windows);
  out.force_N.reserve(windows);
  out.instrument.reserve(windows);
  if (world.nucleus()) {
    out.particles = world.nucleus()->particle_count();
    out.bonds = world.nucleus()->bond_count();
  }
  DeviceSample sample;
  double iterations = 0.0, active = 0.0;
  Vec3 f_sum = Vec3::Zero();
  int f_count = 0;
  auto start = Clock::now();
  double cpu_start = thread_cpu_s();
  for (std::int64_t k = 0; k < steps; ++k) {
    if (k == window.warmup_steps && k > 0) {
      start = Clock::now();
      cpu_start = thread_cpu_s();
    }
    const double t_rel = double(k + 1) * dt;
    sample.t_s = t0 + t_rel;
    sample.pose = trajectory.at(t0 + t_rel);
    const auto step_start = Clock::now();
    const Frame& f = world.step(sample);
    if (observer) observer(world, f);
    out.max_step_wall_s = std::max(
        out.max_step_wall_s, std::chrono::duration<double>(Clock::now() - step_start).count());
    iterations += f.solver_iterations;
    active += f.active_particles;
    f_sum += f.nucleus_force_N;
    ++f_count;
    // Close a force window when this step ends on (or just past) its boundary.
    const double boundary = double(out.t_s.size() + 1) * window.sample_s;
    if (out.t_s.size() < windows && t_rel >= boundary - 1e-9 * dt) {
      out.t_s.push_back(boundary);
      out.force_N.push_back(f_sum / f_count);
      out.instrument.push_back(f.instrument);
      f_sum = Vec3::Zero();
      f_count = 0;
    }
    if (world.failed()) {
      out.failed = true;
      break;
    }
    if (progress && (k % 250 == 0)) progress(double(k) / double(steps));
  }
  out.cpu_s = thread_cpu_s() - cpu_start;
  out.wall_s = std::chrono::duration<double>(Clock::now() - start).count();
  out.steps = world.step_count();
  out.timed_steps = std::max<std::int64_t>(0, out.steps - window.warmup_steps);
  out.sim_s = world.time_s();
  out.mean_iterations = out.steps > 0 ? iterations / out.steps : 0.0;
  out.mean_active = out.steps > 0 ? active / out.steps : 0.0;
  out.stages = world.stage_times();
  out.removed_target = world.last_frame().removed_target;
  out.removed_fraction = world.summary().initial_target > 0
                             ? double(out.removed_target) / world.summary().initial_target
                             : 0.0;
  out.state_hash = world.state_hash();
  if (progress) progress(1.0);
  return out;
}

}  // namespace acdr
