// How a nucleus is built: the solver options that are not part of a scene file, and an
// explicit particle scene given instead of lattice blocks.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "engine/core/types.hpp"

namespace acdr {

/// Solver options that are not part of a scene file (tests, verification and benchmarks set
/// them). Defaults are what the World uses.
struct NucleusOptions {
  /// Interaction radius in units of the spacing h: viscosity acts between particles closer
  /// than this (26 lattice neighbours at 1.98; see viscous_weight_of in nucleus_kernels.hpp,
  /// whose weights are calibrated for this radius).
  double neighbor_radius_factor = 1.98;
  /// Support of the density kernel (pressure), in units of h; at most the interaction radius.
  /// 1.7 reaches the 18 nearest lattice neighbours (at h and sqrt(2) h) with the spiky kernel
  /// still weighting the sqrt(2) h shell (at 1.5 h it nearly vanishes and buoyancy fails).
  double density_radius_factor = 1.7;
  /// Particles are kept this far (in units of h) from solid surfaces: half a spacing, so a
  /// lattice touching a wall fills the space up to it.
  double contact_radius_factor = 0.5;
  /// Springs between particles; false makes the material a pure viscous fluid.
  bool bonds_enabled = true;
  /// Periodic domain along an axis when periodic[a] (for verification flows); positions wrap
  /// into [periodic_min, periodic_max).
  std::array<bool, 3> periodic = {false, false, false};
  Vec3 periodic_min_m = Vec3::Zero();
  Vec3 periodic_max_m = Vec3::Zero();
  /// Upper bound of neighbour pairs per particle (pairs capacity = N * this / 2).
  int max_neighbors = 48;
  /// Verlet skin in units of h: candidate pairs are kept within R + skin and rebuilt once the
  /// two largest displacements since the last build sum to a skin.
  double skin_factor = 0.3;
  /// Index of the static collider whose reaction from the particles is gathered per particle
  /// (static_forces(); the bone, for its finite-element model); -1: none. Only read: the
  /// particles' motion does not depend on it.
  int gathered_static = -1;
};

/// An explicit particle scene (verification, tests): positions, materials, fixed particles
/// and bonds given directly instead of lattice blocks.
struct NucleusParticleSetup {
  struct Bond {
    int i = 0;
    int j = 0;
    double stiffness_N_m = 0.0;
    double break_stretch_m = 0.0;  ///< <= 0: unbreakable
    double rest_length_m = -1.0;   ///< < 0: the initial distance
  };
  std::vector<Vec3> positions_m;
  std::vector<Vec3> velocities_m_s;     ///< empty: at rest
  std::vector<std::uint8_t> materials;  ///< empty: all material 0
  std::vector<std::uint8_t> fixed;      ///< empty: none; 1 = kinematic (never integrated)
  std::vector<Bond> bonds;
};

}  // namespace acdr
