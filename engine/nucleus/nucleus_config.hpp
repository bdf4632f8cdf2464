// What a scene says about its particle material: the materials, the lattice blocks they fill,
// and the solver settings of the implicit step (plain data, SI units).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "engine/core/types.hpp"

namespace acdr {

/// One particle material (nucleus pulposus, annulus). Defaults: the seed's shortening-like
/// nucleus (seed Sec. IV.A: viscosity >= 250 Pa·s) at water-like density (docs/references.md).
struct MaterialConfig {
  std::string name = "nucleus";
  double density_kg_m3 = 1050.0;    ///< gel density, 1000-1100 usual (docs/references.md)
  double viscosity_Pa_s = 250.0;    ///< Newtonian shear viscosity mu (seed Eq. 2-3)
  double bond_stiffness_N_m = 5.0;  ///< spring stiffness k between bonded particles (Eq. 9)
  double bond_break_m = 0.3e-3;     ///< break stretch delta_max; a bond breaks at k*delta_max (Eq. 10)
  bool counts_as_target = true;     ///< removing it is the goal (nucleus) or a penalty (annulus)
  /// Bulk modulus of the particle pressure (density constraint), Pa: a penalty that keeps the
  /// water-rich gel nearly incompressible (hydrostatic compression of a 1 cm layer ~0.2 %).
  /// Not published for NP; 50 kPa is of the order of its measured moduli (5-60 kPa,
  /// docs/references.md) and keeps the buoyancy case within a few percent (docs/verification.md).
  double bulk_modulus_Pa = 5.0e4;
  /// Cohesion: two particles of this material that touch (closer than the bond radius,
  /// NucleusConfig::bond_radius_factor x spacing) without a bond, and have both been at rest
  /// relative to their neighbours for this long, bond again, at their current distance (so
  /// the new bond stores no energy) with this material's stiffness and break stretch: a torn
  /// piece of gel re-adheres to the gel it rests against. 0: never (the seed's model).
  double rebond_time_s = 0.0;
  /// "At rest relative to the neighbours": no neighbour's distance changes faster than this.
  double rebond_speed_m_s = 1.0e-3;
  /// Surface tension of the material's torn faces, N/m: two of its particles that no built
  /// bond joins (the pieces of a cut) attract each other between the lattice spacing and the
  /// bond radius, with the work of separating them that of making two faces of h^2
  /// (engine/nucleus/surface_tension.hpp). 0: none (the seed's model). Water's is 0.070 N/m
  /// at 37 degC (docs/references.md).
  double surface_tension_N_m = 0.0;
};

/// Shapes of particle regions other than a box, for the disc space.
enum class BlockShape : std::uint8_t {
  kBox,               ///< the whole box [min, max]
  kEllipticCylinder,  ///< points of the box inside an elliptic cylinder along `axis`, less an
                      ///< optional elliptic hole: a nucleus (no hole) or an annulus ring
};

/// A region filled with particles on a cubic lattice anchored at `min_m`: the box [min, max],
/// or (anatomy) the part of it inside an elliptic cylinder or ring. Blocks whose `min_m` differ
/// by whole multiples of the spacing share their lattice, so a nucleus, the annulus ring around
/// it and the cartilage endplate layers above and below it meet without a seam.
struct ParticleBlockConfig {
  Vec3 min_m = Vec3::Zero();
  Vec3 max_m = Vec3::Zero();
  int material = 0;  ///< index into NucleusConfig::materials
  BlockShape shape = BlockShape::kBox;
  int axis = 1;                          ///< kEllipticCylinder: 0 x, 1 y, 2 z (the spine: y)
  Vec3 center_m = Vec3::Zero();          ///< ellipse centre (its `axis` coordinate is ignored)
  /// Outer semi-axes along the two other axes, in increasing axis order (for axis y: x then z).
  double semi_a_m = 0.0, semi_b_m = 0.0;
  /// Hole semi-axes (0: none). A ring: the annulus around a nucleus of these semi-axes.
  double hole_a_m = 0.0, hole_b_m = 0.0;
  /// Optional box left empty, e.g. the anterior window cut into the annulus for the approach.
  bool has_cutout = false;
  Vec3 cutout_min_m = Vec3::Zero(), cutout_max_m = Vec3::Zero();

  /// Whether point p belongs to the region (inside the box, the shape, not the hole or cutout).
  bool contains(const Vec3& p) const;
};

struct NucleusConfig {
  bool enabled = false;
  double spacing_m = 1.0e-3;            ///< lattice spacing h of the particles
  double bond_radius_factor = 1.5;      ///< particles closer than factor*h at start are bonded
  std::vector<MaterialConfig> materials;
  std::vector<ParticleBlockConfig> blocks;
};

struct SolverConfig {
  double dt_s = 1.0e-3;          ///< fixed step (1 kHz haptic rate)
  /// The World steps the particles every this many of its steps, at nucleus_every x dt_s;
  /// the instrument, its coupling and contacts, the zones and the feedback still step at dt_s,
  /// the particles' reaction held between their steps (see World). 1: every step.
  int nucleus_every = 1;
  /// Pipelined particle steps: each particle step is launched on a thread of its own at the end
  /// of the due step before, against the instrument where it will be at its own step if it
  /// moves on at its present velocities, and handed on at its own step as if it had run there
  /// (World). When that path would cover more than a quarter of the spacing the due step runs
  /// its particle step itself. The steps between keep pace with the worker, so no step waits
  /// a whole particle step out.
  bool nucleus_pipelined = false;
  /// Where pipelined particle steps run: a thread of their own (true), or at once inside the
  /// step that launches them (false; the same results bit for bit, for tests). Not a scenario
  /// setting.
  bool nucleus_thread = true;
  int max_iterations = 60;       ///< linear solver iterations per substep
  double tolerance = 1.0e-4;     ///< relative residual of the linear solve
  bool sleep_enabled = true;     ///< particles at rest far from the instrument are not integrated
  /// A particle under this speed for 40 ms of simulated time (nucleus_sleep.cpp), farther than
  /// sleep_distance_m from every moving collider, sleeps.
  double sleep_speed_m_s = 1.0e-4;
  double sleep_distance_m = 6.0e-3;
  /// Particle-collider contacts are looked for only where the collider's bounding box comes
  /// within reach of the particle (exact: a box farther away cannot hold a surface nearer).
  /// Off only to measure what the skip saves (acdr bench).
  bool contact_culling = true;
  /// The wall sums a particle gets from a collider's lattice sites (density, second moment,
  /// no-slip tensor; dozens of distance queries) are kept while the particle's place relative
  /// to the collider stays within `wall_sum_cache_tolerance` x spacing (and the collider
  /// turns less than that over the interaction radius): resting material by the box walls or
  /// bone, and material carried on the instrument, skip the queries for a sub-percent lag in
  /// those sums. Off to measure the skip (acdr bench).
  bool wall_sum_cache = true;
  double wall_sum_cache_tolerance = 0.005;
};

}  // namespace acdr
