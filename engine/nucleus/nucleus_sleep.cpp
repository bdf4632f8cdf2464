// Sleep and wake: which particles a step integrates.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "engine/nucleus/nucleus_math.hpp"
#include "engine/nucleus/nucleus_stages.hpp"

namespace acdr::nucleus {
namespace {

// How long a particle stays below the sleep speed before it sleeps, in simulated time (so the
// particles every k-th step, k dt at a time, sleep after the same time as at every step).
constexpr double kCalmTimeToSleep_s = 0.04;

// The calm counter (NucleusState::calm, 16 bits) stops counting here.
constexpr int kCalmCountMax = 60000;

// The particle steps of length dt nearest to kCalmTimeToSleep_s: at least one, and at most
// what the calm counter reaches.
int calm_steps_to_sleep(double dt) {
  return static_cast<int>(
      std::clamp(std::lround(kCalmTimeToSleep_s / dt), 1L, long{kCalmCountMax}));
}

}  // namespace

// Sleep: a particle slower than sleep_speed for a while and farther than sleep_distance from
// every moving collider is frozen (kept out of the solve, acting as a fixed neighbour). It
// wakes when a moving collider comes near, an awake neighbour moves, or a bond of it breaks.
// Only particles that can change state are visited: the awake ones, those queued to wake, and
// those in grid cells near a moving collider.
void wake_and_sleep(const NucleusModel& model, NucleusState& state, NucleusWorkspace& work,
                    std::span<const Collider> moving, double dt) {
  VerletRows& rows = work.rows;
  StepParticles& step = work.step;
  const std::size_t n = state.x.size();
  if (!model.solver.sleep_enabled) {
    // Everything that is not fixed is integrated (the "skip off" case).
    if (state.active_count + state.kinematic_list.size() != n) {
      state.active_count = 0;
      for (std::size_t i = 0; i < n; ++i) {
        state.awake[i] = state.kinematic[i] ? 0 : 1;
        if (state.awake[i]) state.active[state.active_count++] = static_cast<std::int32_t>(i);
      }
    }
    for (std::size_t k = 0; k < state.wake_count; ++k) state.wake_next[state.wake_list[k]] = 0;
    state.wake_count = 0;
    return;
  }
  const double slow2 = model.solver.sleep_speed_m_s * model.solver.sleep_speed_m_s;
  const double sleep_d = model.solver.sleep_distance_m;
  // Waking first, on the states at the start of the step: particles near a moving collider
  // (marked with this step's stamp, which the awake ones' calm count reads below) and those
  // queued (an awake neighbour moved, a bond broke). New awake particles are kept in
  // step.global (free until build_pairs) and appended to the awake list at the end.
  ++work.stamp_value;
  const std::int32_t near_mark = work.stamp_value;
  std::size_t woken = 0;
  auto wake = [&](std::int32_t i) {
    if (state.kinematic[i] || state.awake[i]) return;
    state.awake[i] = 1;
    state.calm[i] = 0;
    step.global[woken++] = i;
  };
  for (const Collider& c : moving) {
    auto test = [&](std::int32_t j) {
      if (work.stamp[j] == near_mark || state.kinematic[j]) return;
      if (!(signed_distance(c, state.x[j], nullptr) < sleep_d)) return;
      work.stamp[j] = near_mark;
      wake(j);
    };
    Vec3 lo, hi;
    if (collider_bounds(c, &lo, &hi)) {
      // The grid holds old positions: the query box is widened by how far they can be off
      // (Up to a skin old: see update_verlet_grid.)
      const Vec3 pad = Vec3::Constant(sleep_d + model.skin);
      rows.grid.for_each_in_box(lo - pad, hi + pad,
                                [&](std::int32_t j, const Vec3&) { test(j); });
    } else {
      for (std::size_t j = 0; j < n; ++j) test(static_cast<std::int32_t>(j));
    }
  }
  const std::size_t was_awake = state.active_count;
  for (std::size_t k = 0; k < state.wake_count; ++k) {
    const std::int32_t i = state.wake_list[k];
    state.wake_next[i] = 0;
    wake(i);
  }
  state.wake_count = 0;
  // Particles awake at the start of the step: calm steps, and sleep after enough of them.
  const int calm_steps = calm_steps_to_sleep(dt);
  std::size_t survivors = 0;
  for (std::size_t k = 0; k < was_awake; ++k) {
    const std::int32_t i = state.active[k];
    const bool calm = work.stamp[i] != near_mark && state.v[i].squaredNorm() < slow2;
    state.calm[i] = calm ? static_cast<std::uint16_t>(std::min(state.calm[i] + 1, kCalmCountMax)) : 0;
    if (state.calm[i] >= calm_steps) {
      state.awake[i] = 0;
      state.v[i] = Vec3::Zero();
      // Its displacement since the grid build stays in the rebuild test (update_verlet_grid).
      const double d2 = min_image(model, state.x[i] - rows.x_built[i]).squaredNorm();
      if (d2 > rows.frozen_disp2[1]) {
        rows.frozen_disp2[1] = d2;
        if (rows.frozen_disp2[1] > rows.frozen_disp2[0])
          std::swap(rows.frozen_disp2[0], rows.frozen_disp2[1]);
      }
    } else {
      state.active[survivors++] = i;
    }
  }
  // The awake list stays sorted by particle index (build_pairs relies on it): the woken ones,
  // sorted, are merged in from the back.
  std::sort(step.global.begin(), step.global.begin() + static_cast<std::ptrdiff_t>(woken));
  std::size_t a = survivors, b = woken, out = survivors + woken;
  while (b > 0) {
    if (a > 0 && state.active[a - 1] > step.global[b - 1])
      state.active[--out] = state.active[--a];
    else
      state.active[--out] = step.global[--b];
  }
  state.active_count = survivors + woken;
}

}  // namespace acdr::nucleus
