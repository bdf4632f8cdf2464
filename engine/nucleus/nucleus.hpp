// The nucleus pulposus (and optional annulus) as particles joined by breakable springs with
// Newtonian viscosity (seed Eq. 2-3, 9-10). Structure of arrays, capacities fixed at build,
// no allocation inside step().
//
// The step is one linearised backward-Euler solve for all particle velocities (see
// nucleus.cpp for the model and the argument for it): viscosity, bond stiffness and a
// density-based pressure are implicit, contacts are velocity constraints inside the solve.
//
// Inside, the data are split as MuJoCo splits mjModel and mjData: a model built once
// (nucleus_model.hpp), a state carried from step to step (nucleus_state.hpp) and a workspace
// the stages of a step fill in turn (nucleus_workspace.hpp); the stages are free functions,
// one file each (nucleus_stages.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "engine/geometry/collider.hpp"
#include "engine/nucleus/nucleus_config.hpp"
#include "engine/nucleus/nucleus_model.hpp"
#include "engine/nucleus/nucleus_options.hpp"
#include "engine/nucleus/nucleus_state.hpp"
#include "engine/nucleus/nucleus_workspace.hpp"

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
          std::span<const Collider> static_colliders, const NucleusOptions& options = {});
  /// An explicit scene; `config` gives spacing and materials, its blocks are ignored.
  Nucleus(const NucleusConfig& config, const SolverConfig& solver, const Vec3& gravity_m_s2,
          std::span<const Collider> static_colliders, const NucleusParticleSetup& setup,
          const NucleusOptions& options = {});

  /// Advances by dt. `moving` are the colliders of moving bodies (the instrument) at their
  /// pose and velocity at the start of the step (they are taken to move on at that velocity
  /// during it); `reactions[b]` receives what the particles do to body b: force, torque about
  /// the `reference_point` already set in it, and drag coefficients (sum of the implicit
  /// no-slip couplings, an upper bound of d|F|/d|v|, so an implicit body update is stable).
  void step(double dt, std::span<const Collider> moving, std::span<BodyReaction> reactions,
            NumericalReport& report);

  std::size_t particle_count() const;
  std::span<const Vec3> positions() const;   ///< N, m
  std::span<const Vec3> velocities() const;  ///< N, m/s
  std::span<const std::uint8_t> materials() const;  ///< N, index into config materials
  double particle_volume_m3() const;          ///< spacing^3
  std::size_t bond_count() const;             ///< bonds at build
  std::size_t broken_bond_count() const;       ///< bonds broken so far (re-formed ones too)
  /// Bonds re-formed so far between touching particles (MaterialConfig::rebond_time_s).
  std::size_t reformed_bond_count() const;
  std::size_t intact_reformed_bond_count() const;  ///< of those, the ones intact now
  /// The re-formed bonds' slots: 2 particles per slot (i < j) and 1 while the slot holds an
  /// intact bond (empty when no material re-bonds).
  std::span<const std::int32_t> reformed_bond_particles() const;
  std::span<const std::uint8_t> reformed_bond_intact() const;
  std::size_t active_count() const;           ///< particles integrated in the last step
  const NucleusConfig& config() const;
  /// FNV-1a over positions and velocities (bit patterns), for determinism tests.
  std::uint64_t state_hash() const;

  // --- extras for verification, tests and benchmarks ---
  std::span<const double> masses() const;        ///< N, kg
  std::span<Vec3> external_forces();             ///< N, N; added every step, caller-owned values
  std::span<const double> pressures() const;     ///< N, Pa, at the end of the last step
  /// N, N: force each particle exerted on the moving bodies in the last step.
  std::span<const Vec3> body_forces() const;
  /// N, N: force each particle exerted on the static collider NucleusOptions::gathered_static
  /// in the last step (zero without one).
  std::span<const Vec3> static_forces() const;
  std::span<const std::uint8_t> bond_alive() const;  ///< bonds at build, 1 while intact
  std::span<const std::int32_t> bond_particles() const;  ///< 2 per bond: i, j
  /// Velocity of a fixed (kinematic) particle; it moves with it. Ignored for free particles.
  void set_fixed_velocity(std::size_t i, const Vec3& v_m_s);
  /// Takes particle i out of the solve (kinematic: it moves at its set_fixed_velocity, its
  /// bonds stretch and break against the free particles, as a grasped piece of gel), or gives
  /// it back (free again, awake at the next step with the velocity it last moved at). Between
  /// steps only; allocates nothing. Particles fixed by the scene stay fixed.
  void set_kinematic(std::size_t i, bool kinematic);
  bool is_kinematic(std::size_t i) const;
  /// The moving colliders change shape from the next step on (another instrument in hand):
  /// the wall sums cached against them are dropped (the statics' are kept).
  void forget_moving_wall_sums();
  /// Between two particle steps of a multi-rate world, while nothing moves: builds now the
  /// neighbour grid and rows that the next step would rebuild, so that step does not carry
  /// them; the same rows from the same positions, so the same results bit for bit.
  void prepare_next_step();
  /// Pipelined multi-rate worlds: the neighbour grid and rows a coming particle step would
  /// rebuild, made ahead beside the step in flight instead of inside a step. reserve once;
  /// begin (at a launch, when the grid in use will probably not hold two particle steps more)
  /// and adopt (at the next launch, when it still holds) between steps, with no step in
  /// flight; build_rows_ahead(share) builds the rows up to that share of the awake particles
  /// and may run while step() runs on another thread (it reads only the copy begin took).
  /// The rows are those a rebuild at the launch's positions makes, so the run is the same on
  /// one thread or two.
  void reserve_rows_ahead();
  bool begin_rows_ahead();
  void build_rows_ahead(double share);
  bool adopt_rows_ahead();
  std::size_t rows_ahead_adopted() const;  ///< grids adopted so far
  std::size_t grid_builds() const;         ///< grids built in a step or adopted so far
  /// The pull of particle i's intact bonds built with the lattice on it (N): the sum of
  /// k (r - L) along the bond toward the other particle, at the current positions.
  Vec3 bond_pull_N(std::size_t i) const;
  void set_gravity(const Vec3& gravity_m_s2);
  std::size_t pair_count() const;               ///< interaction pairs in the last step
  /// Mechanical energy, J: kinetic + gravitational (zero at the origin) + bond springs +
  /// pressure (kappa V C^2 / 2 with C from the last step's pressures) + surface tension
  /// between torn faces (surface_tension.hpp). Without driving it can
  /// only decrease (backward Euler and viscosity dissipate); the stress suite checks that.
  double mechanical_energy_J() const;
  double kinetic_energy_J() const;
  double spacing_m() const;

 private:
  NucleusModel model_;      // built once
  NucleusState state_;      // carried from step to step (hashed: positions, velocities)
  NucleusWorkspace work_;   // what the stages of a step pass on (and the caches)
};

}  // namespace acdr
