// Small scenes the nucleus tests share: two bonded cubes with a gap between them, and a blade
// cutting down into the box block while the heap allocations are counted.
#pragma once

#include <span>
#include <vector>

#include "engine/nucleus/nucleus.hpp"
#include "tests/support/counting_allocator.hpp"

namespace acdr::test {

/// Two 2 x 2 x 2 cubes of bonded particles (bonds within 1.5 spacings) on a lattice of spacing
/// h along x, their facing layers `gap_m` apart and unbonded, of material `m`, no sleep.
struct TwoPieces {
  NucleusConfig config;
  SolverConfig solver;
  NucleusParticleSetup setup;
  std::vector<int> left, right;  // particle indices; [4..7] of left face right[0..3]
};

inline TwoPieces two_pieces(const MaterialConfig& m, double h, double gap_m) {
  TwoPieces s;
  s.config.spacing_m = h;
  s.config.materials = {m};
  s.solver.sleep_enabled = false;
  for (int piece = 0; piece < 2; ++piece)
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        for (int c = 0; c < 2; ++c) {
          (piece == 0 ? s.left : s.right).push_back(static_cast<int>(s.setup.positions_m.size()));
          s.setup.positions_m.push_back(Vec3(piece * (h + gap_m) + a * h, b * h, c * h));
        }
  for (const auto* piece : {&s.left, &s.right})
    for (const int i : *piece)
      for (const int j : *piece)
        if (i < j && (s.setup.positions_m[j] - s.setup.positions_m[i]).norm() < 1.5 * h) {
          NucleusParticleSetup::Bond bond;
          bond.i = i;
          bond.j = j;
          bond.stiffness_N_m = m.bond_stiffness_N_m;
          bond.break_stretch_m = m.bond_break_m;
          s.setup.bonds.push_back(bond);
        }
  return s;
}

/// Heap allocations during `steps` 1 ms steps of `n` while `blade` moves down at 0.1 m/s (after
/// one step that is not counted); `ok` is false if a step reported a numerical failure.
inline long heap_allocations_while_cutting(Nucleus& n, Collider blade, int steps, bool* ok) {
  blade.linear_velocity_m_s = Vec3(0, 0, -0.1);
  BodyReaction reaction;
  NumericalReport r;
  n.step(1e-3, std::span<const Collider>(&blade, 1), std::span<BodyReaction>(&reaction, 1), r);
  *ok = r.ok;
  const long before = test_support::heap_allocations();
  for (int s = 0; s < steps; ++s) {
    blade.pose.position += 1e-3 * blade.linear_velocity_m_s;
    n.step(1e-3, std::span<const Collider>(&blade, 1), std::span<BodyReaction>(&reaction, 1), r);
    *ok = *ok && r.ok;
  }
  return test_support::heap_allocations() - before;
}

}  // namespace acdr::test
