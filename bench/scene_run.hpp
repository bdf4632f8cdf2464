// One benchmark run: a World built from a scene description with chosen solver settings,
// driven by a trajectory over a time window, with the figures the benchmark compares
// (instrument force over time, nucleus removed, wall and CPU time per stage). Shared by the
// `acdr bench` command and the step probe (docs/architecture.md: scene builders are shared,
// never copied).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "engine/devices/trajectory.hpp"
#include "engine/world/world.hpp"
#include "engine/world/world_config.hpp"

namespace acdr {

/// Solver and scene settings a benchmark point varies. Values <= 0 (or -1) keep the scene's.
struct RunSettings {
  double dt_s = 0.0;           ///< fixed step, s (the trajectory is sampled at it)
  int max_iterations = 0;      ///< PCG iterations per step
  double tolerance = 0.0;      ///< relative PCG residual
  double spacing_m = 0.0;      ///< particle spacing h, m (the blocks are refilled at it)
  int sleep = -1;              ///< 1/0: sleeping far particles on/off; -1: the scene's setting
  double sleep_distance_m = 0.0;  ///< particles this near a moving collider stay awake, m
  double sleep_speed_m_s = 0.0;   ///< particles slower than this may sleep, m/s (0: the scene's)
  int nucleus_every = 0;       ///< the particles step every this many steps; 0: the scene's
  int pipelined = -1;          ///< 1/0: pipelined particle steps on/off; -1: the scene's setting
};

/// Applies `s` to a copy of `base`.
WorldConfig apply_settings(const WorldConfig& base, const RunSettings& s);

/// Which part of the trajectory a run plays, and how its force is sampled.
struct RunWindow {
  double start_s = 0.0;     ///< trajectory time the compared and timed window starts at
  double duration_s = 0.0;  ///< simulated time; <= 0: to the end of the trajectory
  /// Simulated time run before the window (the instrument starts on the trajectory there):
  /// round(lead_s / dt) steps that are neither timed nor compared, so the window starts from
  /// the state the run itself reached, not from a fresh lattice with the instrument placed in
  /// it. A whole number of sample windows, so that the instrument poses recorded from the
  /// run's start (RunTrace::instrument) fall on sample boundaries.
  double lead_s = 0.0;
  /// Forces are averaged over consecutive windows of this length (s), so runs at different
  /// steps are compared at the same instants and over the same spans. 12 ms holds an even
  /// number of steps for dt = 0.25, 0.5, 1, 2 and 3 ms, and for the particles' steps of
  /// multi-rate runs at 2 and 3 ms: a force that alternates from step to step (as the
  /// nucleus's did until its contacts only pushed, by up to half its mean) cancels in such a
  /// window, where one of an odd number of steps (10 ms at 2 ms) keeps a remnant of it.
  double sample_s = 0.012;
  /// Steps run before the timing starts (warm-up; their forces still count).
  int warmup_steps = 0;
};

/// What a run produced.
struct RunTrace {
  std::vector<double> t_s;          ///< end of each force window, s after the start
  std::vector<Vec3> force_N;        ///< mean nucleus force on the instrument per window, N
  /// Simulated grip pose at each sample boundary from the run's start (the lead's included):
  /// the path a peer follows from the trajectory's pose at run_start_s(window, dt).
  std::vector<Pose> instrument;
  double removed_fraction = 0.0;    ///< target particles removed at the end / initial
  std::int32_t removed_target = 0;
  std::size_t particles = 0;
  std::size_t bonds = 0;
  double sim_s = 0.0;               ///< simulated time of the window (the lead not counted)
  double wall_s = 0.0;              ///< wall time of the stepping loop (after the warm-up)
  double cpu_s = 0.0;               ///< CPU time of the process in the loop, every thread (robust on a shared machine)
  double max_step_wall_s = 0.0;     ///< slowest single step, wall
  double p99_step_wall_s = 0.0;     ///< 99th percentile of the timed steps' wall times
  std::int64_t steps = 0;           ///< steps in the window (the lead not counted)
  std::int64_t timed_steps = 0;     ///< steps after the warm-up (those wall_s and cpu_s cover)
  double mean_iterations = 0.0;
  double mean_active = 0.0;
  StageTimes stages;
  bool failed = false;
  std::uint64_t state_hash = 0;
};

/// Called after every step (e.g. to draw a frame); its time counts in the run's wall time.
using RunObserver = std::function<void(const World&, const Frame&)>;

/// Steps run before the window at step dt_s: round(window.lead_s / dt_s).
std::int64_t lead_step_count(const RunWindow& window, double dt_s);

/// Trajectory time a run at step dt_s starts at: the window's start less its lead steps.
double run_start_s(const RunWindow& window, double dt_s);

/// Runs `config` along `trajectory` over `window` (its lead first; the observer sees the
/// window's steps only). `progress(fraction)` is called now and
/// then when given.
RunTrace run_scene(const WorldConfig& config, const Trajectory& trajectory,
                   const RunWindow& window, const std::function<void(double)>& progress = {},
                   const RunObserver& observer = {});

/// The instrument's motion along a recorded path over one step.
struct PathMotion {
  Pose pose;                                   ///< on the path at the step's start
  Vec3 velocity_m_s = Vec3::Zero();            ///< reaching the path's position dt later
  Vec3 angular_velocity_rad_s = Vec3::Zero();  ///< reaching its orientation dt later
};

/// CPU time of the whole process, s: every thread's, so a pipelined particle step's worker is
/// counted with the stepping thread (the bench runs nothing else beside its runs).
double process_cpu_s();

/// Pose along a recorded path at time t after its start: path[k] is the pose at
/// (k + 1) * sample_s, `start` the pose at 0; linear in position, slerp in orientation.
Pose pose_on_path(const Pose& start, const std::vector<Pose>& path, double sample_s, double t);

/// The pose on the path (see pose_on_path) at t and the velocities that take it to the path's
/// pose at t + dt.
PathMotion motion_on_path(const Pose& start, const std::vector<Pose>& path, double sample_s,
                          double t, double dt);

}  // namespace acdr
