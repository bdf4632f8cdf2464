// Re-bonding (cohesion): the last stage of a step. A gel is cohesive: a piece torn off and
// laid back against the gel sticks to it again. The seed's model (bonds only between lattice
// neighbours at the start, broken for good) lets every torn piece fall apart into the particles
// whose bonds broke, so removed material scatters like sand. Here two particles of a
// re-bonding material (MaterialConfig::rebond_time_s > 0) that touch without a bond (closer
// than the bond radius) bond again once both have rested relative to their neighbours (no
// neighbour distance changing faster than rebond_speed) for rebond_time; a sleeping particle
// is at rest. The bond is made at the particles' current distance, so it stores no energy
// when made and the step's energy balance is unchanged; it has the material's stiffness and
// break stretch and breaks like a built bond. Material pulled apart faster than the speed
// never rests, so it does not re-join.
//
// Re-formed bonds live in a pool of slots fixed at build (ReformedBonds; no allocation in a
// step). In the pairs and Verlet rows a re-formed bond is bond index B + slot: the rows of both
// particles are patched when one is made or breaks, and rows built later read each
// particle's slots (ensure_row), so the pairs carry it exactly as a built bond and the solve
// treats it implicitly (dt^2 k in the pair coefficient). A re-formed bond is at most
// bond radius + delta_max < R long, so it is always in a pair (never loose).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "engine/nucleus/nucleus_stages.hpp"

namespace acdr::nucleus {
namespace {

constexpr int kPer = ReformedBonds::kPerParticle;

// Sets the bond of j's entry in particle i's Verlet row, if that row is current (a row built
// later reads the particles' slots itself).
void set_row_bond(VerletRows& rows, std::int32_t i, std::int32_t j, std::int32_t bond) {
  if (rows.epoch_of[i] != rows.epoch) return;
  auto set_in = [&](std::int32_t begin, std::int32_t end) {
    for (std::int32_t c = begin; c < end; ++c)
      if (rows.j[c] == j) {
        rows.bond[c] = bond;
        return true;
      }
    return false;
  };
  if (set_in(rows.start[i], rows.start[i] + rows.upper[i])) return;
  if (rows.lower_at[i] >= 0) set_in(rows.lower_at[i], rows.lower_at[i] + rows.lower_len[i]);
}

// The first unused slot entry of particle i, or nullptr when it holds kPer re-formed bonds.
std::int32_t* free_entry(ReformedBonds& reformed, std::int32_t i) {
  std::int32_t* of = reformed.of.data() + static_cast<std::size_t>(i) * kPer;
  for (int a = 0; a < kPer; ++a)
    if (of[a] < 0) return of + a;
  return nullptr;
}

void remove_entry(ReformedBonds& reformed, std::int32_t i, std::int32_t slot) {
  std::int32_t* of = reformed.of.data() + static_cast<std::size_t>(i) * kPer;
  for (int a = 0; a < kPer; ++a)
    if (of[a] == slot) {
      of[a] = -1;
      return;
    }
}

}  // namespace

void release_reformed_bond(NucleusState& state, VerletRows& rows, std::int32_t slot) {
  ReformedBonds& reformed = state.reformed;
  const std::int32_t i = reformed.ij[2 * slot], j = reformed.ij[2 * slot + 1];
  reformed.alive[slot] = 0;
  remove_entry(reformed, i, slot);
  remove_entry(reformed, j, slot);
  reformed.free[reformed.free_count++] = slot;
  set_row_bond(rows, i, j, -1);
  set_row_bond(rows, j, i, -1);
}

void reform_bonds(const NucleusModel& model, NucleusState& state, NucleusWorkspace& work,
                  double dt) {
  if (!model.rebonding) return;
  const StepParticles& step = work.step;
  const PairList& pairs = work.pairs;
  ReformedBonds& reformed = state.reformed;
  const auto& materials = model.config.materials;
  // How fast each particle's distance to a neighbour changes (the near pairs with an awake
  // particle, end-of-step velocities; a sleeping particle's is zero). A rigid motion, turning
  // included, changes no distance.
  double* rate2 = work.separation_rate2.data();
  for (std::size_t k = 0; k < step.halo_end; ++k) rate2[k] = 0.0;
  for (std::size_t p = 0; p < pairs.near_awake; ++p) {
    const std::int32_t li = pairs.i[p], lj = pairs.j[p];
    const double rate = pairs.n[p].dot(state.v[step.global[lj]] - state.v[step.global[li]]);
    const double r2 = rate * rate;
    rate2[li] = std::max(rate2[li], r2);
    rate2[lj] = std::max(rate2[lj], r2);
  }
  for (std::size_t k = 0; k < step.awake_end; ++k) {
    const std::int32_t i = step.global[k];
    const MaterialConfig& mat = materials[model.material[i]];
    if (!(mat.rebond_time_s > 0.0)) continue;
    const bool resting = rate2[k] < mat.rebond_speed_m_s * mat.rebond_speed_m_s;
    reformed.settled_s[i] = resting ? reformed.settled_s[i] + dt : 0.0;
  }
  // Touching pairs without a bond (none at the start of the step, or one that broke in it),
  // of one re-bonding material, both rested long enough.
  const std::int32_t nb = static_cast<std::int32_t>(model.bonds.size());
  const double bond_r2 = model.bond_radius * model.bond_radius;
  for (std::size_t p = 0; p < pairs.near_awake && reformed.free_count > 0; ++p) {
    if (pairs.bond[p] >= 0) continue;
    const std::int32_t li = pairs.i[p], lj = pairs.j[p];
    const std::int32_t i = step.global[li], j = step.global[lj];
    if (model.material[i] != model.material[j] || state.kinematic[i] || state.kinematic[j]) continue;
    const MaterialConfig& mat = materials[model.material[i]];
    if (!(mat.rebond_time_s > 0.0) || !(mat.bond_stiffness_N_m > 0.0) ||
        !(mat.bond_break_m > 0.0))
      continue;
    // The pair's first end is awake; the second may sleep (at rest).
    if (reformed.settled_s[i] < mat.rebond_time_s) continue;
    if (lj < static_cast<std::int32_t>(step.awake_end) &&
        reformed.settled_s[j] < mat.rebond_time_s)
      continue;
    const double r2 = min_image(model, state.x[j] - state.x[i]).squaredNorm();
    if (!(r2 < bond_r2) || !(r2 > 0.0)) continue;
    const double r = std::sqrt(r2);
    if (!(r + mat.bond_break_m < model.radius)) continue;  // could outgrow R: never made
    std::int32_t* entry_i = free_entry(reformed, i);
    std::int32_t* entry_j = free_entry(reformed, j);
    if (entry_i == nullptr || entry_j == nullptr) continue;
    const std::int32_t s = reformed.free[--reformed.free_count];
    reformed.ij[2 * s] = std::min(i, j);
    reformed.ij[2 * s + 1] = std::max(i, j);
    reformed.rest[s] = r;
    reformed.k[s] = mat.bond_stiffness_N_m;
    const double hi = r + mat.bond_break_m, lo = r - mat.bond_break_m;
    reformed.break_hi2[s] = hi * hi;
    reformed.break_lo2[s] = lo > 0.0 ? lo * lo : 0.0;
    reformed.alive[s] = 1;
    *entry_i = s;
    *entry_j = s;
    ++reformed.made;
    set_row_bond(work.rows, i, j, nb + s);
    set_row_bond(work.rows, j, i, nb + s);
  }
}

}  // namespace acdr::nucleus
