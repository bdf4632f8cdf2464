// Bond breaking: the last stage of a step but one (re-bonding follows it).
#include <cstddef>
#include <cstdint>

#include "engine/nucleus/nucleus_stages.hpp"

namespace acdr::nucleus {

// Bonds break when their force exceeds k * delta_max, i.e. |stretch| > delta_max
// (seed Eq. 9-10). Only bonds of awake or fixed particles can have changed length. Bond
// indices from B on are re-formed bonds (nucleus_cohesion.cpp), tested the same way.
void break_bonds(const NucleusModel& model, NucleusState& state, NucleusWorkspace& work) {
  const PairList& pairs = work.pairs;
  const LooseBonds& loose = work.loose;
  const std::int32_t nb = static_cast<std::int32_t>(model.bonds.size());
  ReformedBonds& reformed = state.reformed;
  auto test = [&](std::int32_t b) {
    const bool built = b < nb;
    const std::int32_t s = b - nb;  // slot of a re-formed bond
    if (built ? !state.bond_alive[b] : !reformed.alive[s]) return;
    const std::int32_t* ij = built ? &model.bonds.ij[2 * b] : &reformed.ij[2 * s];
    const std::int32_t i = ij[0], j = ij[1];
    // |r - L| > delta  <=>  r^2 > (L + delta)^2 or r^2 < (L - delta)^2 (the latter only
    // when L > delta): no square root per bond. An unbreakable bond (delta <= 0) has the
    // bounds +inf and 0, which no r^2 passes, so it needs no test of its own.
    const double r2 = min_image(model, state.x[j] - state.x[i]).squaredNorm();
    const double hi2 = built ? model.bonds.break_hi2[b] : reformed.break_hi2[s];
    const double lo2 = built ? model.bonds.break_lo2[b] : reformed.break_lo2[s];
    if (r2 > hi2 || r2 < lo2) {
      if (built) state.bond_alive[b] = 0;
      else release_reformed_bond(state, work.rows, s);
      ++state.broken_bonds;
      for (const std::int32_t e : {i, j}) {
        if (state.kinematic[e] || state.wake_next[e]) continue;
        state.wake_next[e] = 1;
        state.wake_list[state.wake_count++] = e;
      }
    }
  };
  // Every live bond of an awake particle is carried by exactly one of this step's pairs with
  // an awake particle (it was shorter than R at the start) or is a loose bond.
  for (std::size_t p = 0; p < pairs.near_awake; ++p)
    if (pairs.bond[p] >= 0) test(pairs.bond[p]);
  for (std::size_t p = pairs.cap - pairs.far_awake; p < pairs.cap; ++p)
    if (pairs.bond[p] >= 0) test(pairs.bond[p]);
  for (std::size_t k = 0; k < loose.count; ++k) test(loose.bond[k]);
  // Kinematic particles move too: all their bonds (one shared with an awake particle is tested
  // again, with the same result). Re-formed bonds never join a particle fixed by the model,
  // but one a grasp holds may have had some before it was taken.
  const bool any_reformed = reformed.capacity() > 0;
  for (const std::int32_t u : state.kinematic_list) {
    for (std::int32_t a = model.bonds.adj_start[u]; a < model.bonds.adj_start[u + 1]; ++a)
      test(model.bonds.adj[a]);
    if (!any_reformed) continue;
    for (int q = 0; q < ReformedBonds::kPerParticle; ++q) {
      const std::int32_t s = reformed.of[static_cast<std::size_t>(u) * ReformedBonds::kPerParticle + q];
      if (s >= 0) test(nb + s);
    }
  }
}

}  // namespace acdr::nucleus
