// The stepping loop every benchmark run shares (a World along a trajectory, the nucleus alone
// along a recorded path, the Bullet peer): a fixed number of steps, the force on the instrument
// averaged over consecutive sample windows, wall and CPU time from the end of the warm-up, the
// slowest step, progress. What a step does is the caller's.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "bench/scene_run.hpp"

namespace acdr {

/// What one step of a run reports to the loop.
struct LoopStep {
  Vec3 force_N = Vec3::Zero();     ///< force on the instrument over the step, N
  std::optional<Pose> instrument;  ///< grip pose at the step's end, kept at window ends (none:
                                   ///< the run records no instrument path)
  bool stop = false;               ///< the run failed: no further steps
};

/// The nearest-rank percentile (0 < fraction <= 1) of `values` (reordered); 0 when empty.
double nearest_rank_percentile(std::vector<double>& values, double fraction);

/// Steps in a run of `duration_s` at `dt_s`: round(duration / dt).
std::int64_t run_step_count(double duration_s, double dt_s);

/// Runs `step(k)` for k = 0, 1, ...: first the window's lead (lead_step_count(window, dt_s)
/// steps, neither timed nor compared), then the window, round(duration / dt) steps, or until a
/// step says stop. Fills `out`'s force windows (t_s and force_N, the window's only, t_s from
/// the window's start), its instrument poses (at every sample boundary from the run's start,
/// where the steps give a pose), wall_s and cpu_s (over the window's steps after
/// window.warmup_steps), timed_steps, max_step_wall_s and p99_step_wall_s (over the timed
/// steps); calls `progress(fraction)` every 250 steps and at the end when given. Returns the
/// number of window steps run.
std::int64_t run_timed_loop(double duration_s, double dt_s, const RunWindow& window, RunTrace& out,
                            const std::function<LoopStep(std::int64_t)>& step,
                            const std::function<void(double)>& progress = {});

}  // namespace acdr
