// One benchmark run: a World built from a scene description with chosen solver settings,
// driven by a trajectory for a given simulated time, with the figures the benchmark compares
// (instrument force over time, nucleus removed, wall time per stage). Shared by the `acdr
// bench` command, the probe program and the micro-benchmarks (STYLE.md: scene builders are
// shared, never copied).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "engine/trajectory.hpp"
#include "engine/world.hpp"
#include "engine/world_config.hpp"

namespace acdr {

/// Solver and scene settings a benchmark point varies. Values <= 0 keep the scene's own.
struct RunSettings {
  double dt_s = 0.0;           ///< fixed step, s (the trajectory is resampled at it)
  int max_iterations = 0;      ///< PCG iterations per step
  double tolerance = 0.0;      ///< relative PCG residual
  double spacing_m = 0.0;      ///< particle spacing h, m (the blocks are refilled at it)
  int sleep = -1;              ///< 1/0 sleeping far particles on/off, -1 the scene's setting
};

/// Applies `s` to a copy of `base`.
WorldConfig apply_settings(const WorldConfig& base, const RunSettings& s);

/// What a run produced. Force samples are taken every `sample_dt_s` of simulated time (the
/// same instants for every run, whatever its step), so runs at different steps compare.
struct RunTrace {
  std::vector<double> t_s;          ///< sample times
  std::vector<double> force_N;      ///< |nucleus force on the instrument| at those times, N
  std::vector<Vec3> force_vec_N;    ///< the vector, N
  double removed_fraction = 0.0;    ///< target particles removed at the end / initial
  std::int32_t removed_target = 0;
  std::size_t particles = 0;
  std::size_t bonds = 0;
  double sim_s = 0.0;               ///< simulated time
  double wall_s = 0.0;              ///< wall time of the stepping loop
  double cpu_s = 0.0;               ///< CPU time of this thread in the loop (robust on a shared machine)
  std::int64_t steps = 0;
  double mean_iterations = 0.0;
  double mean_active = 0.0;
  StageTimes stages;
  bool failed = false;
  std::uint64_t state_hash = 0;
};

/// Runs `config` along `trajectory` from 0 to `duration_s` (<= 0: the trajectory's length).
/// `progress(fraction)` is called now and then when given.
RunTrace run_scene(const WorldConfig& config, const Trajectory& trajectory, double duration_s,
                   double sample_dt_s = 1e-3,
                   const std::function<void(double)>& progress = {});

}  // namespace acdr
