// Rows ahead: in a pipelined multi-rate world the particle step runs on a thread of its own
// while the world's steps between go on, and a step that rebuilds the neighbour grid costs
// about twice an ordinary one. The rebuild is made ahead instead, on the world's thread, from a
// copy of the state at a launch, and the particle step after next adopts it.
//
// Why it is sound: rows built from positions x0 hold every pair closer than R at positions x
// while the two largest displacements |x - x0| sum to less than the skin (update_verlet_grid).
// Adoption measures exactly that bound for the built grid at the positions of the adopting
// launch, over every particle, and keeps the sleepers' part as the grid's frozen
// displacements; the step then goes on testing it as for a grid it built itself. A grid that
// does not hold is dropped and the step rebuilds as before. The rows are those a rebuild at
// the copy's positions would make; they differ from the rows of a rebuild one particle step
// later only in the positions they were built from, so a pipelined run differs in its bits
// from one that rebuilds in the step (not in what a pair is), and is the same on one thread
// or two.
#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "engine/nucleus/nucleus_stages.hpp"

namespace acdr::nucleus {
namespace {

constexpr double kGrowthMargin = 1.5;

}  // namespace

void reserve_rows_ahead(const NucleusModel& model, NucleusWorkspace& work) {
  const std::size_t n = model.particle_count();
  RowsAhead& ahead = work.ahead;
  reserve_rows(model, n, ahead.rows);
  ahead.x.assign(n, Vec3::Zero());
  ahead.bond_alive.assign(model.bonds.size(), 0);
  ahead.awake.assign(n, 0);
  ahead.awake_count = ahead.built = 0;
  ahead.pending = false;
}

// Begun when the grid in use will probably not hold at the step after next: its bound now plus
// 1.5 times its growth over the last particle step reaches the skin. The coming step tests the
// bound at these same positions, so it is safe with the grid in use; the step after it tests
// the bound one particle step on, so waiting for the next launch is safe only while the bound
// grows by less than the skin left (1.5: a margin for the growth changing from one particle
// step to the next, by up to a fifth in the full-size disc's traced windows; a step that finds
// its grid gone rebuilds it itself). Not when the
// coming step rebuilds anyway, nor with re-bonding (its bonds change the rows inside a grid
// build) or periodic axes.
bool begin_rows_ahead(const NucleusModel& model, const NucleusState& state,
                      NucleusWorkspace& work) {
  RowsAhead& ahead = work.ahead;
  const VerletRows& rows = work.rows;
  if (ahead.x.size() != state.x.size() || state.x.empty() || ahead.pending) return false;
  if (model.rebonding || model.periodic || !rows.grid_valid) return false;
  const double bound = verlet_displacement_bound(model, state, rows);
  const double growth =
      ahead.last_grid == rows.grid_builds ? std::max(bound - ahead.last_bound_m, 0.0) : bound;
  ahead.last_bound_m = bound;
  ahead.last_grid = rows.grid_builds;
  if (!(bound < model.skin) || bound + kGrowthMargin * growth < model.skin) return false;

  std::copy(state.x.begin(), state.x.end(), ahead.x.begin());
  std::copy(state.bond_alive.begin(), state.bond_alive.end(), ahead.bond_alive.begin());
  std::copy(state.active.begin(),
            state.active.begin() + static_cast<std::ptrdiff_t>(state.active_count),
            ahead.awake.begin());
  ahead.awake_count = state.active_count;  // (the order rows are built in changes no row)
  ahead.built = 0;
  ahead.rows.grid_valid = false;  // built with the first share
  ahead.pending = true;
  return true;
}

// Reads only the copy and writes only the spare rows: safe beside a particle step in flight.
void build_rows_ahead(const NucleusModel& model, RowsAhead& ahead, double share) {
  if (!ahead.pending) return;
  VerletRows& next = ahead.rows;
  if (!next.grid_valid) {
    build_verlet_grid(model, ahead.x, next);
    next.overflowed_ahead = false;
  }
  const double want = std::ceil(std::clamp(share, 0.0, 1.0) * double(ahead.awake_count));
  const std::size_t until = std::min(ahead.awake_count, static_cast<std::size_t>(want));
  if (until <= ahead.built) return;
  const RowInputs in{ahead.bond_alive, nullptr, ahead.awake_count == ahead.x.size()};
  build_rows_of(model, in, next,
                std::span<const std::int32_t>(ahead.awake.data() + ahead.built, until - ahead.built));
  ahead.built = until;
}

bool adopt_rows_ahead(const NucleusModel& model, const NucleusState& state,
                      NucleusWorkspace& work) {
  RowsAhead& ahead = work.ahead;
  if (!ahead.pending) return false;
  build_rows_ahead(model, ahead, 1.0);
  ahead.pending = false;
  VerletRows& next = ahead.rows;
  // The bound since its build: the moving particles' displacements (awake, kinematic) and the
  // sleepers', which stay frozen in it until they wake.
  std::array<double, 2> moving = {0.0, 0.0}, frozen = {0.0, 0.0};
  for (std::size_t i = 0; i < state.x.size(); ++i) {
    const double d2 = min_image(model, state.x[i] - next.x_built[i]).squaredNorm();
    note_two_largest(d2, state.awake[i] || state.kinematic[i] ? moving : frozen);
  }
  std::array<double, 2> all = moving;
  note_two_largest(frozen[0], all);
  note_two_largest(frozen[1], all);
  const double bound = std::sqrt(all[0]) + std::sqrt(all[1]);
  if (!(bound < model.skin)) return false;
  const std::size_t builds = work.rows.grid_builds;
  std::swap(work.rows, next);
  work.rows.grid_builds = builds + 1;
  work.rows.frozen_disp2 = frozen;
  work.rows.disp_bound = bound;
  ++ahead.adopted;
  return true;
}

}  // namespace acdr::nucleus
