// Bond breaking: the last stage of a step.
#include <cstddef>
#include <cstdint>

#include "engine/nucleus/nucleus_stages.hpp"

namespace acdr::nucleus {

// Bonds break when their force exceeds k * delta_max, i.e. |stretch| > delta_max
// (seed Eq. 9-10). Only bonds of awake or fixed particles can have changed length.
void break_bonds(const NucleusModel& model, NucleusState& state, const NucleusWorkspace& work) {
  const PairList& pairs = work.pairs;
  const LooseBonds& loose = work.loose;
  auto test = [&](std::int32_t b) {
    if (!state.bond_alive[b]) return;
    const std::int32_t i = model.bonds.ij[2 * b], j = model.bonds.ij[2 * b + 1];
    // |r - L| > delta  <=>  r^2 > (L + delta)^2 or r^2 < (L - delta)^2 (the latter only
    // when L > delta): no square root per bond. An unbreakable bond (delta <= 0) has the
    // bounds +inf and 0, which no r^2 passes, so it needs no test of its own.
    const double r2 = min_image(model, state.x[j] - state.x[i]).squaredNorm();
    if (r2 > model.bonds.break_hi2[b] || r2 < model.bonds.break_lo2[b]) {
      state.bond_alive[b] = 0;
      ++state.broken_bonds;
      for (const std::int32_t e : {i, j}) {
        if (model.fixed[e] || state.wake_next[e]) continue;
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
  // Fixed particles move too: all their bonds (one shared with an awake particle is tested
  // again, with the same result).
  for (const std::int32_t u : model.fixed_list)
    for (std::int32_t a = model.bonds.adj_start[u]; a < model.bonds.adj_start[u + 1]; ++a)
      test(model.bonds.adj[a]);
}

}  // namespace acdr::nucleus
