// The nucleus pulposus (and optional annulus) as particles joined by breakable springs with
// Newtonian viscosity (seed Eq. 2-3, 9-10). Structure of arrays, capacities fixed at build,
// no allocation inside step().
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "engine/collider.hpp"
#include "engine/world_config.hpp"

namespace acdr {

/// Numerical trouble found during a step (reported by the World as an event, never hidden).
struct NumericalReport {
  bool ok = true;
  const char* stage = "";  ///< the stage that produced the first NaN/Inf or blow-up
  int iterations = 0;      ///< linear solver iterations used
  double residual = 0.0;   ///< final relative residual
};

class Nucleus {
 public:
  /// Fills the configured blocks with particles on a cubic lattice, clipped by the static
  /// colliders (no particle starts inside a solid), and bonds neighbours.
  Nucleus(const NucleusConfig& config, const SolverConfig& solver, const Vec3& gravity_m_s2,
          std::span<const Collider> static_colliders);

  /// Advances by dt. `moving` are the colliders of moving bodies (the instrument) at their
  /// current pose and velocity; `reactions[b]` receives what the particles do to body b.
  void step(double dt, std::span<const Collider> moving, std::span<BodyReaction> reactions,
            NumericalReport& report);

  std::size_t particle_count() const;
  std::span<const Vec3> positions() const;   ///< N, m
  std::span<const Vec3> velocities() const;  ///< N, m/s
  std::span<const std::uint8_t> materials() const;  ///< N, index into config materials
  double particle_volume_m3() const;          ///< spacing^3
  std::size_t bond_count() const;             ///< bonds at build
  std::size_t broken_bond_count() const;
  std::size_t active_count() const;           ///< particles integrated in the last step
  const NucleusConfig& config() const;
  /// FNV-1a over positions and velocities (bit patterns), for determinism tests.
  std::uint64_t state_hash() const;

  // ... private state owned by the implementation
};

}  // namespace acdr
