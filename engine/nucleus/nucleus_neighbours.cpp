// Neighbours: the Verlet rows (rebuilt lazily after the grid is), and this step's local
// numbering, pairs and loose bonds built from them.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>

#include <emmintrin.h>

#include "engine/nucleus/nucleus_stages.hpp"

namespace acdr::nucleus {

// The grid of the Verlet rows is rebuilt once two particles together have moved a skin since
// the last build: a pair closer than R now was closer than R + |dx_i| + |dx_j| then, so no
// such pair can be missing from the rows while the two largest displacements sum to less than
// the skin (the usual test, every particle within skin / 2, is the special case of equal
// ones; this one tolerates a few fast particles among slow ones). Only awake and kinematic
// particles move; those that fell asleep keep the displacement they had
// (rows.frozen_disp2).
void note_two_largest(double d2, std::array<double, 2>& m) {
  if (d2 <= m[1]) return;  // NaN counts as largest
  if (!(d2 <= m[0])) {
    m[1] = m[0];
    m[0] = d2;
  } else {
    m[1] = d2;
  }
}

double verlet_displacement_bound(const NucleusModel& model, const NucleusState& state,
                                 const VerletRows& rows) {
  std::array<double, 2> m = rows.frozen_disp2;
  auto note = [&](std::int32_t i) {
    note_two_largest(min_image(model, state.x[i] - rows.x_built[i]).squaredNorm(), m);
  };
  for (std::size_t k = 0; k < state.active_count; ++k) note(state.active[k]);
  for (const std::int32_t i : state.kinematic_list) note(i);
  return std::sqrt(m[0]) + std::sqrt(m[1]);
}

void build_verlet_grid(const NucleusModel& model, std::span<const Vec3> x, VerletRows& rows) {
  rows.disp_bound = 0.0;
  rows.frozen_disp2 = {0.0, 0.0};
  rows.grid.build(x, model.radius + model.skin, model.options.periodic,
                  model.options.periodic_min_m, model.options.periodic_max_m);
  std::copy(x.begin(), x.end(), rows.x_built.begin());
  ++rows.epoch;
  rows.used = 0;
  rows.grid_valid = true;
}

void update_verlet_grid(const NucleusModel& model, const NucleusState& state, VerletRows& rows) {
  rows.disp_bound = verlet_displacement_bound(model, state, rows);
  const bool rebuild = !rows.grid_valid || !(rows.disp_bound < model.skin);
  if (!rebuild) return;
  build_verlet_grid(model, state.x, rows);
  ++rows.grid_builds;
}

namespace {

constexpr int kReformed = ReformedBonds::kPerParticle;

// The other particle of the re-formed bond in slot s, seen from particle i.
std::int32_t reformed_other(const ReformedBonds& reformed, std::int32_t s, std::int32_t i) {
  const std::int32_t a = reformed.ij[2 * s], b = reformed.ij[2 * s + 1];
  return a == i ? b : a;
}

// Row i's bonds by partner in rows.partner_bond (a live bond wins over a broken one between the
// same particles; re-formed bonds are index B + slot, only between particles without a live
// built bond), or (set = false) those marks cleared again.
void mark_partners(const NucleusModel& model, const RowInputs& in, VerletRows& rows,
                   std::int32_t i, bool set) {
  for (std::int32_t k = model.bonds.adj_start[i]; k < model.bonds.adj_start[i + 1]; ++k) {
    const std::int32_t b = model.bonds.adj[k];
    const std::int32_t other = model.bonds.other(b, i);
    if (!set)
      rows.partner_bond[other] = -1;
    else if (rows.partner_bond[other] < 0 || !in.bond_alive[rows.partner_bond[other]])
      rows.partner_bond[other] = b;
  }
  if (!model.rebonding) return;
  const ReformedBonds& reformed = *in.reformed;
  const std::int32_t* reformed_of = reformed.of.data() + static_cast<std::size_t>(i) * kReformed;
  for (int a = 0; a < kReformed; ++a)
    if (const std::int32_t s = reformed_of[a]; s >= 0)
      rows.partner_bond[reformed_other(reformed, s, i)] =
          set ? static_cast<std::int32_t>(model.bonds.size()) + s : -1;
}

// Which entries of a row row_part() computes: all of them, the upper part only (the lower one
// deferred), or the deferred lower part.
enum class RowPart { kWhole, kUpper, kLower };

// Appends the entries of row i's `part` to the pool: every particle within R + skin of i at
// the last grid build (above i for the upper part, below it for the lower), with the bond
// between them (-1 if none), and sets where they are. Returns false, having appended nothing,
// when an upper part is asked for and the whole row is too long to order (see below).
bool row_part(const NucleusModel& model, const RowInputs& in, VerletRows& rows,
              std::int32_t i, RowPart part, bool& overflow) {
  const double reach = model.radius + model.skin;
  const double reach2 = reach * reach;
  mark_partners(model, in, rows, i, true);
  const std::size_t start = rows.used;
  const std::size_t cap = rows.j.size();
  const Vec3 xi = rows.x_built[i];
  // Each entry's ordering bucket (see below): higher index first, then lower; within each,
  // inside the density radius, inside R, then beyond (at the build positions).
  const double Rd2 = model.density_radius * model.density_radius;
  const double R2 = model.radius * model.radius;
  const std::size_t scratch = rows.scratch_j.size();
  std::array<std::int32_t, 7> count{};
  std::size_t left = 0;  // entries of the other part, not kept
  auto keep = [&](std::int32_t j, double r2) {
    if (j == i) return;
    if (part != RowPart::kWhole && (j < i) != (part == RowPart::kLower)) {
      ++left;
      return;
    }
    if (rows.used >= cap) {
      overflow = true;
      return;
    }
    // (Rd <= R: build_model caps the density radius at R.)
    const int bucket = 3 * int(j < i) + int(r2 >= Rd2) + int(r2 >= R2);
    const std::size_t c = rows.used - start;
    if (c < scratch) {
      rows.scratch_bucket[c] = static_cast<std::uint8_t>(bucket);
      rows.scratch_r2[c] = static_cast<float>(r2);
    }
    ++count[bucket + 1];
    rows.j[rows.used] = j;
    rows.bond[rows.used] = rows.partner_bond[j];
    ++rows.used;
  };
  if (model.periodic) {
    rows.grid.for_each_near(xi, [&](std::int32_t j, const Vec3& xj) {
      if (j == i) return;
      const double r2 = min_image(model, xj - xi).squaredNorm();
      if (r2 < reach2) keep(j, r2);
    });
  } else {
    rows.grid.for_each_within(xi, reach2, keep);
  }
  mark_partners(model, in, rows, i, false);
  const std::size_t len = rows.used - start;
  if (part == RowPart::kUpper && len + left > scratch) {
    rows.used = start;
    return false;
  }
  // Order by bucket (stable counting sort; see VerletRows::upper). A row longer than the
  // scratch is only split into its upper and lower parts (the ordering only saves time).
  std::int32_t upper = 0, beyond = 0;
  if (len <= scratch) {
    std::copy(rows.j.begin() + start, rows.j.begin() + rows.used, rows.scratch_j.begin());
    std::copy(rows.bond.begin() + start, rows.bond.begin() + rows.used,
              rows.scratch_bond.begin());
    for (int b = 0; b < 6; ++b) count[b + 1] += count[b];
    upper = count[3];
    beyond = count[2];
    for (std::size_t c = 0; c < len; ++c) {
      const std::size_t at = start + count[rows.scratch_bucket[c]]++;
      rows.j[at] = rows.scratch_j[c];
      rows.bond[at] = rows.scratch_bond[c];
      rows.r2[at] = rows.scratch_r2[c];
    }
  } else {
    // Unordered (whole rows only: a row's part is left for later only when the whole row fits
    // the scratch): upper/lower partition only (in place, order within the parts lost).
    std::size_t lo = start, hi = rows.used;
    while (lo < hi) {
      if (rows.j[lo] > i) {
        ++lo;
      } else {
        --hi;
        std::swap(rows.j[lo], rows.j[hi]);
        std::swap(rows.bond[lo], rows.bond[hi]);
      }
    }
    upper = static_cast<std::int32_t>(lo - start);
    beyond = upper;
  }
  if (part == RowPart::kLower) {
    rows.lower_at[i] = static_cast<std::int32_t>(start);
    rows.lower_len[i] = static_cast<std::int32_t>(len);
    return true;
  }
  rows.start[i] = static_cast<std::int32_t>(start);
  rows.upper[i] = upper;
  rows.beyond[i] = beyond;
  rows.lower_at[i] = part == RowPart::kUpper ? -1 : static_cast<std::int32_t>(start) + upper;
  rows.lower_len[i] = static_cast<std::int32_t>(len) - upper;
  return true;
}

// Row i, computed at most once per grid build, when i first takes part in a step. While every
// particle is awake no step reads a lower part (an awake neighbour below i pairs with i from
// its own row, and there is no halo), so a row's lower part is then left until a step does
// (ensure_lower_part): the same entries in the same order, from the same grid and bonds. Not
// with re-bonding, whose bonds change inside a grid build, nor on periodic axes.
void ensure_row(const NucleusModel& model, const RowInputs& in, VerletRows& rows,
                std::int32_t i, bool& overflow) {
  if (rows.epoch_of[i] == rows.epoch) return;
  rows.epoch_of[i] = rows.epoch;
  const bool defer = !model.rebonding && !model.periodic && in.all_awake;
  if (defer && row_part(model, in, rows, i, RowPart::kUpper, overflow)) return;
  row_part(model, in, rows, i, RowPart::kWhole, overflow);
}

// The lower part of row i (its row is current), if it was left for later.
void ensure_lower_part(const NucleusModel& model, const RowInputs& in, VerletRows& rows,
                       std::int32_t i, bool& overflow) {
  if (rows.lower_at[i] < 0) row_part(model, in, rows, i, RowPart::kLower, overflow);
}

}  // namespace

RowInputs row_inputs(const NucleusState& state) {
  return {state.bond_alive, &state.reformed, state.active_count == state.x.size()};
}

void prepare_rows(const NucleusModel& model, NucleusState& state, VerletRows& rows) {
  const std::uint32_t epoch = rows.epoch;
  update_verlet_grid(model, state, rows);
  if (rows.epoch == epoch) return;  // the rows in place still hold
  const RowInputs in = row_inputs(state);
  for (std::size_t k = 0; k < state.active_count; ++k)
    ensure_row(model, in, rows, state.active[k], rows.overflowed_ahead);
}

void build_rows_of(const NucleusModel& model, const RowInputs& in, VerletRows& rows,
                   std::span<const std::int32_t> particles) {
  for (const std::int32_t i : particles) ensure_row(model, in, rows, i, rows.overflowed_ahead);
}

namespace {

// Builds this step's local numbering and pairs (see build_pairs). Pairs split by reach: near
// ones (density radius) from the front of the arrays, far ones from the back.
class PairBuilder {
 public:
  PairBuilder(const NucleusModel& model, NucleusState& state, NucleusWorkspace& work)
      : model_(model), state_(state), rows_(work.rows), step_(work.step), pairs_(work.pairs),
        loose_(work.loose), work_(work), R2_(model.radius * model.radius),
        Rd2_(model.density_radius * model.density_radius), cap_(work.pairs.cap),
        nb_(static_cast<std::int32_t>(model.bonds.size())), in_(row_inputs(state)) {}

  // The awake particles take the first local numbers, in the order of the awake list.
  void number_awake() {
    pairs_.near = pairs_.far = 0;
    if (rows_.overflowed_ahead) pairs_.overflow = true;  // a row built ahead ran out of room
    rows_.overflowed_ahead = false;
    step_.awake_end = state_.active_count;
    for (std::size_t k = 0; k < step_.awake_end; ++k) {
      const std::int32_t i = state_.active[k];
      step_.global[k] = i;
      step_.local[i] = static_cast<std::int32_t>(k);
      step_.x_start[i] = state_.x[i];
    }
    step_.halo_end = step_.awake_end;
    // This step's stamp for the bonds its pairs carry (find_loose_bonds); on the wrap of the
    // counter (after 2^32 - 1 steps) the old marks are cleared so none can match it.
    if (model_.bonds.loose_possible && ++loose_.stamp == 0) {
      std::fill(loose_.in_pair.begin(), loose_.in_pair.end(), 0u);
      loose_.stamp = 1;
    }
  }

  // Awake rows. The awake list is sorted by particle index, so an awake neighbour numbered
  // below k is exactly an awake neighbour of lower index: the row's upper part (higher
  // indices) is paired whole, its lower part only with particles that are not awake. Rows are
  // ordered by distance within each part, so the range and near/far tests branch alike from
  // row to row. Sleeping neighbours within R join the step as the halo.
  void pair_awake_rows() {
    const bool propagate_wake = model_.solver.sleep_enabled;
    const double slow2 = model_.solver.sleep_speed_m_s * model_.solver.sleep_speed_m_s;
    bool mark_lower = false;
    const std::int32_t lower_mark = mark_rows_with_lower_sleepers(&mark_lower);
    // An entry of the upper part's beyond bucket that was at least R + rows.disp_bound away
    // at the build is at least R away now (no particle has moved farther; a 1e-6 relative
    // margin covers the single-precision distances): the range test below would reject it,
    // so it is skipped on its build distance alone. (Periodic domains: not used.)
    const double reach_now = (model_.radius + rows_.disp_bound) * (1.0 + 1e-6);
    const float far2 = model_.periodic ? std::numeric_limits<float>::infinity()
                                       : static_cast<float>(reach_now * reach_now * (1.0 + 1e-6));
    for (std::size_t k = 0; k < step_.awake_end; ++k) {
      const std::int32_t i = open_row(k);
      const std::int32_t* rj = rows_.j.data() + rows_.start[i];
      const std::int32_t* rb = rows_.bond.data() + rows_.start[i];
      const std::int32_t upper = rows_.upper[i];
      const Vec3 xi = state_.x[i];
      // Wake propagation for the next step: a frozen neighbour of a moving particle wakes.
      const bool moving_i = propagate_wake && state_.v[i].squaredNorm() >= slow2;
      auto visit = [&](std::int32_t j, std::int32_t bond) {
        const Vec3 d = min_image(model_, state_.x[j] - xi);
        const double r2 = d.squaredNorm();
        if (r2 >= R2_ || r2 <= 0.0) return;
        std::int32_t lj = step_.local[j];
        if (lj < 0) {
          lj = static_cast<std::int32_t>(step_.halo_end++);
          step_.local[j] = lj;
          step_.global[lj] = j;
        }
        if (moving_i && lj >= static_cast<std::int32_t>(step_.awake_end) && !state_.kinematic[j] &&
            !state_.wake_next[j]) {
          state_.wake_next[j] = 1;
          state_.wake_list[state_.wake_count++] = j;
        }
        emit(static_cast<std::int32_t>(k), lj, d, r2, bond);
      };
      const float* rr = rows_.r2.data() + rows_.start[i];
      const std::int32_t beyond = rows_.beyond[i];
      for (std::int32_t c = 0; c < beyond; ++c) visit(rj[c], rb[c]);
      for (std::int32_t c = beyond; c < upper; ++c)
        if (rr[c] < far2) visit(rj[c], rb[c]);
      if (!mark_lower || work_.stamp[i] == lower_mark) {
        ensure_lower_part(model_, in_, rows_, i, pairs_.overflow);
        const std::int32_t* lj = rows_.j.data() + rows_.lower_at[i];
        const std::int32_t* lb = rows_.bond.data() + rows_.lower_at[i];
        for (std::int32_t c = 0; c < rows_.lower_len[i]; ++c)
          if (!state_.awake[lj[c]]) visit(lj[c], lb[c]);
      }
    }
    pairs_.near_awake = pairs_.near;
    pairs_.far_awake = pairs_.far;
  }

  // The halo's rows give the remaining pairs (the halo's densities must be complete); their
  // neighbours not yet in the step join it as the outer particles.
  void pair_halo_rows() {
    step_.outer_end = step_.halo_end;
    for (std::size_t k = step_.awake_end; k < step_.halo_end; ++k) pair_row(k, step_.outer_end);
    pairs_.row_near[step_.halo_end] = static_cast<std::int32_t>(pairs_.near);
    pairs_.row_far[step_.halo_end] = static_cast<std::int32_t>(pairs_.far);
    pairs_.count = pairs_.near + pairs_.far;
  }

  // Bonds stretched beyond the interaction radius (possible only when delta_max > R - L) are
  // applied on their own; the other end joins the step if it is not in it yet.
  // A live bond is at most L + delta_max long at the start of a step (longer ones broke at the
  // end of the last one), so when every bond's L + delta_max is inside R there are none.
  void find_loose_bonds() {
    const BondTable& bonds = model_.bonds;
    loose_.count = 0;
    for (std::size_t k = 0; k < (bonds.loose_possible ? step_.awake_end : 0); ++k) {
      const std::int32_t i = step_.global[k];
      for (std::int32_t a = bonds.adj_start[i]; a < bonds.adj_start[i + 1]; ++a) {
        const std::int32_t b = bonds.adj[a];
        if (!state_.bond_alive[b] || loose_.in_pair[b] == loose_.stamp) continue;
        const std::int32_t j = bonds.other(b, i);
        std::int32_t lj = step_.local[j];
        if (lj >= 0 && lj < static_cast<std::int32_t>(k)) continue;  // awake, counted from j
        if (lj < 0) {
          lj = static_cast<std::int32_t>(step_.outer_end++);
          step_.local[j] = lj;
          step_.global[lj] = j;
        }
        // Oriented as the bond is (i -> j in bond order), like a pair.
        const bool forward = bonds.ij[2 * b] == i;
        loose_.bond[loose_.count] = b;
        loose_.ij[2 * loose_.count] = forward ? static_cast<std::int32_t>(k) : lj;
        loose_.ij[2 * loose_.count + 1] = forward ? lj : static_cast<std::int32_t>(k);
        ++loose_.count;
      }
    }
  }

  // Every pair's length r from r^2 and its direction d / r, in one pass over the pairs after
  // they are all found: the square roots and divisions, on two lanes at a time, no longer
  // wait on each other inside the branchy pairing loops. (The same correctly rounded
  // operations as one at a time, so the same bits.)
  void normalise_pairs() {
    normalise_range(0, pairs_.near);
    normalise_range(cap_ - pairs_.far, cap_);
  }

  void note_frozen_moving() {
    step_.frozen_moving = false;
    for (std::size_t k = step_.awake_end; k < step_.outer_end; ++k)
      step_.frozen_moving = step_.frozen_moving || state_.kinematic[step_.global[k]];
  }

 private:
  // Pair (li, lj) with d = x_j - x_i and r2 = |d|^2, near or far by r2, with its live bond.
  void emit(std::int32_t li, std::int32_t lj, const Vec3& d, double r2, std::int32_t bond) {
    if (pairs_.near + pairs_.far >= cap_) {
      pairs_.overflow = true;
      return;
    }
    const std::size_t p = r2 < Rd2_ ? pairs_.near++ : cap_ - 1 - pairs_.far++;
    pairs_.i[p] = li;
    pairs_.j[p] = lj;
    pairs_.r[p] = r2;  // r and n = d / r come in normalise_pairs()
    pairs_.n[p] = d;
    if (bond >= 0 && !bond_intact(model_, state_, bond)) bond = -1;
    pairs_.bond[p] = bond;
    // (Re-formed bonds, from index B on, are never loose.)
    if (bond >= 0 && model_.bonds.loose_possible && bond < nb_) loose_.in_pair[bond] = loose_.stamp;
  }

  void normalise_range(std::size_t begin, std::size_t end) {
    double* r = pairs_.r.data();
    Vec3* n = pairs_.n.data();
    std::size_t p = begin;
    for (; p + 1 < end; p += 2) {
      const __m128d len = _mm_sqrt_pd(_mm_loadu_pd(r + p));
      _mm_storeu_pd(r + p, len);
      const __m128d inv = _mm_div_pd(_mm_set1_pd(1.0), len);
      n[p] *= _mm_cvtsd_f64(inv);
      n[p + 1] *= _mm_cvtsd_f64(_mm_unpackhi_pd(inv, inv));
    }
    if (p < end) {
      r[p] = std::sqrt(r[p]);
      n[p] *= 1.0 / r[p];
    }
  }

  // Starts local particle k's pairs: its Verlet row (built if needed) and where its near and
  // far pairs begin.
  std::int32_t open_row(std::size_t k) {
    const std::int32_t i = step_.global[k];
    ensure_row(model_, in_, rows_, i, pairs_.overflow);
    pairs_.row_near[k] = static_cast<std::int32_t>(pairs_.near);
    pairs_.row_far[k] = static_cast<std::int32_t>(pairs_.far);
    return i;
  }

  // The pairs of local particle k from its row. A neighbour numbered below k was paired from
  // its own side (awake ones before halo ones, halo ones by index; self never appears); one
  // not numbered yet joins the step with the next local number from `next` (the halo for
  // awake particles, the outer ring for halo ones).
  void pair_row(std::size_t k, std::size_t& next) {
    const std::int32_t i = open_row(k);
    ensure_lower_part(model_, in_, rows_, i, pairs_.overflow);
    const Vec3 xi = state_.x[i];
    // The upper part, then the lower one.
    for (const auto& [at, n] : {std::pair{rows_.start[i], rows_.upper[i]},
                               std::pair{rows_.lower_at[i], rows_.lower_len[i]}}) {
      const std::int32_t* rj = rows_.j.data() + at;
      const std::int32_t* rb = rows_.bond.data() + at;
      for (std::int32_t c = 0; c < n; ++c) {
        const std::int32_t j = rj[c];
        std::int32_t lj = step_.local[j];
        if (lj >= 0 && lj < static_cast<std::int32_t>(k)) continue;
        const Vec3 d = min_image(model_, state_.x[j] - xi);
        const double r2 = d.squaredNorm();
        if (r2 >= R2_ || r2 <= 0.0) continue;
        if (lj < 0) {
          lj = static_cast<std::int32_t>(next++);
          step_.local[j] = lj;
          step_.global[lj] = j;
        }
        emit(static_cast<std::int32_t>(k), lj, d, r2, rb[c]);
      }
    }
  }

  // Lower parts pair only the particles that are not awake. When there are few of those, the
  // rows that can hold one are marked from its side (the returned stamp; *marked set), and
  // the others skip their lower part: a non-awake j is in the lower part of row i only if
  // i > j lies in the 27 grid cells around j's build position (the cells are neighbours of
  // each other both ways).
  std::int32_t mark_rows_with_lower_sleepers(bool* marked) {
    const std::size_t n_all = state_.x.size();
    const bool mark_lower = (n_all - step_.awake_end) * 16 <= step_.awake_end;
    *marked = mark_lower;
    std::int32_t lower_mark = 0;
    if (mark_lower) {
      lower_mark = ++work_.stamp_value;
      std::size_t a = 0;
      for (std::size_t j = 0; j < n_all; ++j) {
        const std::int32_t jj = static_cast<std::int32_t>(j);
        if (a < step_.awake_end && state_.active[a] == jj) {
          ++a;
          continue;
        }
        rows_.grid.for_each_near(rows_.x_built[j], [&](std::int32_t i, const Vec3&) {
          if (i > jj) work_.stamp[i] = lower_mark;
        });
      }
    }
    return lower_mark;
  }

  const NucleusModel& model_;
  NucleusState& state_;
  VerletRows& rows_;
  StepParticles& step_;
  PairList& pairs_;
  LooseBonds& loose_;
  NucleusWorkspace& work_;
  const double R2_, Rd2_;
  const std::size_t cap_;
  const std::int32_t nb_;  // bonds at build: higher bond indices are re-formed ones
  const RowInputs in_;     // what rows built lazily read (the awake list is final here)
};

}  // namespace

// This step's particles in local numbering and their pairs. The awake particles' rows give
// the pairs with an awake particle and, as their sleeping neighbours within R, the halo; the
// halo's rows give the remaining pairs (the halo's densities must be complete) and the outer
// particles. Pairs split by reach: near ones (density radius) from the front of the arrays,
// far ones from the back.
void build_pairs(const NucleusModel& model, NucleusState& state, NucleusWorkspace& work) {
  PairBuilder builder(model, state, work);
  builder.number_awake();
  builder.pair_awake_rows();
  builder.pair_halo_rows();
  builder.normalise_pairs();
  builder.find_loose_bonds();
  builder.note_frozen_moving();
}

}  // namespace acdr::nucleus
