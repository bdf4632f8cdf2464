// The benchmark runs' shared stepping loop (see the header).
#include "bench/run_loop.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

namespace acdr {

double nearest_rank_percentile(std::vector<double>& values, double fraction) {
  if (values.empty()) return 0.0;
  // The smallest value at or above `fraction` of them.
  const double n = static_cast<double>(values.size());
  const auto rank = static_cast<std::size_t>(std::clamp(std::ceil(fraction * n), 1.0, n)) - 1;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(rank),
                   values.end());
  return values[rank];
}

std::int64_t lead_step_count(const RunWindow& window, double dt_s) {
  return window.lead_s > 0.0 ? run_step_count(window.lead_s, dt_s) : 0;
}

double run_start_s(const RunWindow& window, double dt_s) {
  return window.start_s - double(lead_step_count(window, dt_s)) * dt_s;
}

std::int64_t run_step_count(double duration_s, double dt_s) {
  return static_cast<std::int64_t>(std::llround(duration_s / dt_s));
}

std::int64_t run_timed_loop(double duration_s, double dt_s, const RunWindow& window, RunTrace& out,
                            const std::function<LoopStep(std::int64_t)>& step,
                            const std::function<void(double)>& progress) {
  using Clock = std::chrono::steady_clock;
  const std::int64_t lead = lead_step_count(window, dt_s);
  const std::int64_t steps = run_step_count(duration_s, dt_s);
  const std::int64_t total = lead + steps;
  const auto windows = static_cast<std::size_t>(std::floor(duration_s / window.sample_s + 1e-9));
  const auto lead_windows =
      static_cast<std::size_t>(std::floor(double(lead) * dt_s / window.sample_s + 1e-9));
  out.t_s.reserve(windows);
  out.force_N.reserve(windows);
  out.instrument.reserve(lead_windows + windows);
  std::vector<double> step_wall;  // timed steps' wall times, for the percentile
  step_wall.reserve(static_cast<std::size_t>(std::max<std::int64_t>(0, steps)));
  Vec3 f_sum = Vec3::Zero();
  int f_count = 0;
  auto start = Clock::now();
  double cpu_start = process_cpu_s();
  std::int64_t ran = 0;
  for (std::int64_t k = 0; k < total; ++k) {
    const std::int64_t kw = k - lead;  // step in the window (negative in the lead)
    if (kw == window.warmup_steps) {
      start = Clock::now();
      cpu_start = process_cpu_s();
    }
    const auto step_start = Clock::now();
    const LoopStep s = step(k);
    const double step_s = std::chrono::duration<double>(Clock::now() - step_start).count();
    if (kw >= 0) {
      out.max_step_wall_s = std::max(out.max_step_wall_s, step_s);
      if (kw >= window.warmup_steps) step_wall.push_back(step_s);
      ++ran;
    }
    // The instrument's pose at every sample boundary from the run's start.
    const double t_run = double(k + 1) * dt_s;
    const double pose_boundary = double(out.instrument.size() + 1) * window.sample_s;
    if (s.instrument && out.instrument.size() < lead_windows + windows &&
        t_run >= pose_boundary - 1e-9 * dt_s)
      out.instrument.push_back(*s.instrument);
    if (kw >= 0) {
      f_sum += s.force_N;
      ++f_count;
      // Close a force window when this step ends on (or just past) its boundary.
      const double t_rel = double(kw + 1) * dt_s;
      const double boundary = double(out.t_s.size() + 1) * window.sample_s;
      if (out.t_s.size() < windows && t_rel >= boundary - 1e-9 * dt_s) {
        out.t_s.push_back(boundary);
        out.force_N.push_back(f_sum / f_count);
        f_sum = Vec3::Zero();
        f_count = 0;
      }
    }
    if (s.stop) break;
    if (progress && (k % 250 == 0)) progress(double(k) / double(total));
  }
  out.cpu_s = process_cpu_s() - cpu_start;
  out.wall_s = std::chrono::duration<double>(Clock::now() - start).count();
  out.timed_steps = std::max<std::int64_t>(0, ran - window.warmup_steps);
  out.p99_step_wall_s = nearest_rank_percentile(step_wall, 0.99);
  if (progress) progress(1.0);
  return ran;
}

}  // namespace acdr
