// Benchmark runs of a World along a trajectory.
#include "bench/scene_run.hpp"

#include "bench/run_loop.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>

namespace acdr {

double process_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
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
  if (s.sleep_distance_m > 0.0) c.solver.sleep_distance_m = s.sleep_distance_m;
  if (s.sleep_speed_m_s > 0.0) c.solver.sleep_speed_m_s = s.sleep_speed_m_s;
  if (s.nucleus_every > 0) c.solver.nucleus_every = s.nucleus_every;
  if (s.pipelined >= 0) c.solver.nucleus_pipelined = s.pipelined != 0;
  return c;
}

PathMotion motion_on_path(const Pose& start, const std::vector<Pose>& path, double sample_s,
                          double t, double dt) {
  PathMotion m;
  m.pose = pose_on_path(start, path, sample_s, t);
  const Pose next = pose_on_path(start, path, sample_s, t + dt);
  m.velocity_m_s = (next.position - m.pose.position) / dt;
  Quat dq = next.orientation * m.pose.orientation.conjugate();
  if (dq.w() < 0) dq.coeffs() *= -1.0;  // the shorter of the two rotations
  const Eigen::AngleAxisd aa(dq);
  m.angular_velocity_rad_s = aa.axis() * (aa.angle() / dt);
  return m;
}

RunTrace run_scene(const WorldConfig& config_in, const Trajectory& trajectory,
                   const RunWindow& window, const std::function<void(double)>& progress,
                   const RunObserver& observer) {
  RunTrace out;
  WorldConfig config = config_in;
  const double dt = config.solver.dt_s;
  const std::int64_t lead = lead_step_count(window, dt);
  const double t0 = run_start_s(window, dt);
  config.instrument_start = trajectory.at(t0);
  World world(config);
  const double duration =
      window.duration_s > 0.0 ? window.duration_s : trajectory.duration_s() - window.start_s;
  if (world.nucleus()) {
    out.particles = world.nucleus()->particle_count();
    out.bonds = world.nucleus()->bond_count();
  }
  DeviceSample sample;
  double iterations = 0.0, active = 0.0;
  StageTimes lead_stages;  // the stage times at the window's start
  run_timed_loop(
      duration, dt, window, out,
      [&](std::int64_t k) {
        if (k == lead) lead_stages = world.stage_times();
        const double t_run = double(k + 1) * dt;
        sample.t_s = t0 + t_run;
        sample.pose = trajectory.at(t0 + t_run);
        const Frame& f = world.step(sample);
        if (k >= lead) {
          if (observer) observer(world, f);
          iterations += f.solver_iterations;
          active += f.active_particles;
        }
        return LoopStep{f.nucleus_force_N, f.instrument, world.failed()};
      },
      progress);
  out.failed = world.failed();
  out.steps = std::max<std::int64_t>(0, world.step_count() - lead);
  out.sim_s = double(out.steps) * dt;
  out.mean_iterations = out.steps > 0 ? iterations / out.steps : 0.0;
  out.mean_active = out.steps > 0 ? active / out.steps : 0.0;
  out.stages = world.stage_times();
  for (std::size_t s = 0; s < out.stages.seconds.size(); ++s)
    out.stages.seconds[s] -= lead_stages.seconds[s];
  out.stages.steps -= lead_stages.steps;
  out.removed_target = world.last_frame().removed_target;
  out.removed_fraction = world.summary().initial_target > 0
                             ? double(out.removed_target) / world.summary().initial_target
                             : 0.0;
  out.state_hash = world.state_hash();
  return out;
}

}  // namespace acdr
