// Benchmark runs of a World along a trajectory.
#include "bench/scene_run.hpp"

#include <chrono>
#include <cmath>
#include <ctime>

namespace acdr {
namespace {

/// CPU time of the calling thread, s.
double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

}  // namespace

WorldConfig apply_settings(const WorldConfig& base, const RunSettings& s) {
  WorldConfig c = base;
  if (s.dt_s > 0.0) c.solver.dt_s = s.dt_s;
  if (s.max_iterations > 0) c.solver.max_iterations = s.max_iterations;
  if (s.tolerance > 0.0) c.solver.tolerance = s.tolerance;
  if (s.spacing_m > 0.0) c.nucleus.spacing_m = s.spacing_m;
  if (s.sleep >= 0) c.solver.sleep_enabled = s.sleep != 0;
  return c;
}

RunTrace run_scene(const WorldConfig& config, const Trajectory& trajectory, double duration_s,
                   double sample_dt_s, const std::function<void(double)>& progress) {
  RunTrace out;
  World world(config);
  const double dt = config.solver.dt_s;
  const double duration = duration_s > 0.0 ? duration_s : trajectory.duration_s();
  const auto steps = static_cast<std::int64_t>(std::llround(duration / dt));
  const auto samples = static_cast<std::size_t>(std::floor(duration / sample_dt_s + 1e-9));
  out.t_s.reserve(samples);
  out.force_N.reserve(samples);
  out.force_vec_N.reserve(samples);
  if (world.nucleus()) {
    out.particles = world.nucleus()->particle_count();
    out.bonds = world.nucleus()->bond_count();
  }
  DeviceSample sample;
  sample.pose = config.instrument_start;
  double iterations = 0.0, active = 0.0;
  // Force samples: the value of the step that ends at or after each sample instant, linearly
  // interpolated between the two steps around it.
  std::size_t next = 0;
  Vec3 f_prev = Vec3::Zero();
  double t_prev = 0.0;
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = thread_cpu_s();
  for (std::int64_t k = 0; k < steps; ++k) {
    const double t_next = (k + 1) * dt;
    sample.t_s = t_next;
    sample.pose = trajectory.at(t_next);
    const Frame& f = world.step(sample);
    iterations += f.solver_iterations;
    active += f.active_particles;
    while (next < samples && (next + 1) * sample_dt_s <= t_next + 1e-12) {
      const double ts = (next + 1) * sample_dt_s;
      const double a = (ts - t_prev) / (t_next - t_prev);
      const Vec3 fs = (1.0 - a) * f_prev + a * f.nucleus_force_N;
      out.t_s.push_back(ts);
      out.force_vec_N.push_back(fs);
      out.force_N.push_back(fs.norm());
      ++next;
    }
    f_prev = f.nucleus_force_N;
    t_prev = t_next;
    if (world.failed()) {
      out.failed = true;
      break;
    }
    if (progress && (k % 500 == 0)) progress(double(k) / double(steps));
  }
  out.cpu_s = thread_cpu_s() - cpu_start;
  out.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.steps = world.step_count();
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
