// The nucleus pulposus (and optional annulus) as particles joined by breakable springs with
// Newtonian viscosity (seed Eq. 2-3, 9-10). Structure of arrays, capacities fixed at build,
// no allocation inside step().
//
// The step is one linearised backward-Euler solve for all particle velocities (see
// nucleus.cpp for the model and the argument for it): viscosity, bond stiffness and a
// density-based pressure are implicit, contacts are velocity constraints inside the solve.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "engine/geometry/collider.hpp"
#include "engine/nucleus/neighbor_grid.hpp"
#include "engine/nucleus/particle_grid.hpp"
#include "engine/nucleus/nucleus_config.hpp"

namespace acdr {

/// Numerical trouble found during a step (reported by the World as an event, never hidden).
struct NumericalReport {
  bool ok = true;
  const char* stage = "";  ///< the stage that produced the first NaN/Inf or blow-up
  int iterations = 0;      ///< linear solver iterations used
  double residual = 0.0;   ///< final relative residual
};

/// Solver options that are not part of a scene file (tests, verification and benchmarks set
/// them). Defaults are what the World uses.
struct NucleusOptions {
  /// Interaction radius in units of the spacing h: viscosity acts between particles closer
  /// than this (26 lattice neighbours at 1.98; see viscous_weight_of in nucleus.cpp, whose
  /// weights are calibrated for this radius).
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
  std::size_t broken_bond_count() const;
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
  void set_gravity(const Vec3& gravity_m_s2);
  std::size_t pair_count() const;               ///< interaction pairs in the last step
  /// Mechanical energy, J: kinetic + gravitational (zero at the origin) + bond springs +
  /// pressure (kappa V C^2 / 2 with C from the last step's pressures). Without driving it can
  /// only decrease (backward Euler and viscosity dissipate); the stress suite checks that.
  double mechanical_energy_J() const;
  double kinetic_energy_J() const;
  double spacing_m() const;

 private:
  void init(std::span<const Collider> static_colliders, const NucleusParticleSetup& setup);
  void update_grid();
  void ensure_row(std::int32_t i);
  void wake_and_sleep(std::span<const Collider> moving, double dt);
  void build_pairs();
  void setup_walls(double dt, std::span<const Collider> moving);
  void assemble(double dt);
  void apply(const Vec3* x, Vec3* y, bool full);
  void solve(NumericalReport& report);
  void reactions_and_pressure(double dt, std::span<const Collider> moving,
                              std::span<BodyReaction> reactions);
  void integrate_and_project(double dt, std::span<const Collider> moving,
                             std::span<BodyReaction> reactions);
  void break_bonds();
  Vec3 min_image(const Vec3& d) const;
  struct WallTableEntry {
    double n = 0.0;       // density share
    double s2 = 0.0;      // second-moment share, m^2
    double grad = 0.0;    // d(density)/dd / n0 along the normal, 1/m
    double visc_n = 0.0;  // no-slip tensor, normal component
    double visc_t = 0.0;  // no-slip tensor, tangential components
  };
  struct SiteSums;
  SiteSums site_sums(const Collider& c, std::int32_t kc, const Vec3& x, const Vec3& local,
                     double d) const;
  void collider_frames(std::span<const Collider> moving);
  const SiteSums& cached_site_sums(std::int32_t kc, const Collider& c, std::int32_t i,
                                   const Vec3& x, double d);
  bool flat_face(const Collider& c, const Vec3& x, double d, const Vec3& normal, int* axis) const;
  void build_wall_table();
  WallTableEntry wall_table_at(double d) const;

  NucleusConfig config_;
  SolverConfig solver_;
  NucleusOptions options_;
  Vec3 gravity_;
  bool periodic_ = false;  // any periodic axis (min_image is the identity otherwise)
  std::vector<Collider> statics_;

  double h_ = 1e-3;       // spacing, m
  double volume_ = 1e-9;  // h^3, m^3
  double radius_ = 1.5e-3;   // interaction radius R, m
  double contact_ = 0.5e-3;  // contact distance from surfaces, m
  double n0_ = 1.0;          // rest number density sum (kernel units) of the full lattice
  double s0_ = 1.0;          // rest weighted second moment sum w r^2 of the full lattice, m^2
  double t0_ = 1.0;          // rest weighted fourth moment sum w r_x^2 r_z^2 / r^2, m^2
  double density_radius_ = 1.5e-3;  // density kernel support, m
  std::vector<Vec3> site_offset_;  // lattice neighbour offsets within R, m
  std::vector<double> site_w_;     // their kernel weights
  std::vector<double> site_r2_;    // their squared lengths, m^2
  std::vector<double> site_wv_;    // their viscous weights
  std::vector<double> site_len_;   // their lengths, m
  std::vector<Eigen::Matrix3d> site_uu_;  // u u^T of their unit directions u
  std::array<WallTableEntry, 1024> wall_table_{};  // flat-face wall sums over d
  double wall_table_lo_ = 0.0, wall_table_step_ = 1.0;

  // ---- Particles, by particle index (N each) ----
  std::vector<Vec3> x_;          // positions, m
  std::vector<Vec3> v_;          // velocities, m/s
  std::vector<Vec3> x_start_;    // positions at step start (awake particles), m
  std::vector<Vec3> f_ext_;      // external forces, N
  std::vector<Vec3> fixed_v_;    // prescribed velocity of fixed particles, m/s
  std::vector<double> mass_;     // kg
  std::vector<double> mu_;       // viscosity, Pa s
  std::vector<double> kappa_;    // bulk modulus, Pa
  std::vector<std::uint8_t> material_;
  std::vector<std::uint8_t> fixed_;   // 1 = kinematic
  std::vector<std::uint8_t> awake_;   // 1 = integrated this step
  std::vector<std::uint8_t> wake_next_;  // 1 = wakes next step (also listed in wake_list_)
  std::vector<std::uint16_t> calm_;   // consecutive calm steps
  std::vector<std::uint8_t> release_;  // 1: a contact pulled last step; skip once
  std::vector<double> pressure_;       // Pa, end of the last step
  std::vector<Vec3> body_force_;       // N, force on moving bodies by particle, last step
  std::vector<Vec3> static_force_;     // N, force on the gathered static collider, last step
  std::vector<std::int32_t> active_;   // awake particles this step, ascending
  std::size_t active_count_ = 0;
  std::vector<std::int32_t> fixed_list_;  // the fixed particles
  std::vector<std::int32_t> wake_list_;   // particles with wake_next_ set
  std::size_t wake_count_ = 0;
  std::vector<std::int32_t> stamp_;       // N, scratch marks (wake candidates)
  std::int32_t stamp_value_ = 0;

  // ---- Bonds (B each) ----
  std::vector<std::int32_t> bond_ij_;  // 2B
  std::vector<double> bond_rest_;      // m
  std::vector<double> bond_k_;         // N/m
  std::vector<double> bond_break_;     // m, <= 0 unbreakable
  std::vector<double> bond_break_hi2_;  // m^2, (L + delta)^2: longer breaks (+inf: never)
  std::vector<double> bond_break_lo2_;  // m^2, (L - delta)^2: shorter breaks (0: never)
  std::vector<std::uint8_t> bond_alive_;
  std::vector<std::uint8_t> bond_in_pair_;  // 1 while a pair of this step carries it
  std::size_t broken_ = 0;
  std::vector<std::int32_t> bond_adj_start_;  // N + 1: bonds of each particle (CSR)
  std::vector<std::int32_t> bond_adj_;        // 2B bond indices
  // Bonds applied on their own this step (stretched beyond R, so in no pair).
  std::vector<std::int32_t> loose_;     // bond index
  std::vector<std::int32_t> loose_ij_;  // 2 per loose bond: local indices
  std::vector<Vec3> loose_n_;           // unit direction i -> j
  std::vector<double> loose_a_;         // dt^2 k
  std::size_t loose_bonds_ = 0;
  bool loose_possible_ = true;          // some bond can outgrow R (unbreakable, or L + delta >= R)

  // ---- Neighbour rows: a Verlet list (Verlet 1967) per particle ----
  // Row i holds every particle within R + skin of i at the last grid build. Rows stay exact
  // until two particles have moved a skin together since that build (update_grid); then the
  // grid is rebuilt and rows are recomputed lazily, only for particles that take part in a step.
  double skin_ = 0.0;
  ParticleGrid grid_;
  std::vector<Vec3> x_built_;              // N, positions at the last grid build
  bool grid_valid_ = false;
  // Two largest squared displacements since the build of particles that fell asleep, m^2.
  std::array<double, 2> frozen_disp2_ = {0.0, 0.0};
  std::uint32_t epoch_ = 0;                // grid builds so far
  std::vector<std::uint32_t> row_epoch_;   // N, epoch a row was computed in (0: none)
  std::vector<std::int32_t> row_start_;    // N, offset into row_j_
  std::vector<std::int32_t> row_len_;      // N
  std::vector<std::int32_t> row_j_;        // pool: candidate particle
  std::vector<std::int32_t> row_bond_;     // pool: their bond (any state), -1 if none
  // N: how many of row i's entries (its first ones) have an index above i; each part of the
  // row is ordered inside the density radius / inside R / beyond, at the grid build.
  std::vector<std::int32_t> row_upper_;
  // N: where row i's upper part's "beyond" bucket (beyond R at the build) starts (== its
  // upper count for an unordered row), and the pool's squared distances at the build (m^2,
  // ordered rows only): an entry farther than R + disp_bound_ then cannot be within R now.
  std::vector<std::int32_t> row_beyond_;
  std::vector<float> row_r2_;
  // The two largest displacements since the grid build, summed (update_grid), m.
  double disp_bound_ = 0.0;
  std::vector<std::int32_t> row_scratch_j_, row_scratch_b_;  // one row, for ordering it
  std::vector<float> row_scratch_r2_;
  std::vector<std::uint8_t> row_scratch_bucket_;
  std::size_t row_used_ = 0;
  std::vector<std::int32_t> partner_bond_; // N, scratch (-1)
  bool pairs_overflow_ = false;
  std::size_t grid_builds_ = 0;

  // ---- This step's particles in a compact local numbering ----
  // Local [0, na_) are the awake particles (ascending index), [na_, nh_) the halo (asleep
  // within R of an awake one; their density must be complete), [nh_, nl_) the outer ones
  // (neighbours of the halo, seen only through their positions and velocities).
  std::vector<std::int32_t> local_;   // N: particle -> local index, -1 if not in the step
  std::vector<std::int32_t> lg_;      // local -> particle
  std::size_t na_ = 0, nh_ = 0, nl_ = 0;
  bool frozen_moving_ = false;        // a halo/outer particle is fixed and moves

  // ---- Pairs of this step (capacity P) ----
  // Near pairs (closer than the density radius; they carry pressure too) fill [0, near_)
  // from the front, those with an awake particle first: [0, near_awake_). Far pairs fill
  // [cap - far_, cap) from the back, those with an awake particle last:
  // [cap - far_awake_, cap). The solver's iterations need only the pairs with an awake
  // particle (the others see zero velocities).
  std::vector<std::int32_t> pair_i_, pair_j_;  // local indices
  std::vector<Vec3> pair_n_;           // unit vector i -> j
  std::vector<double> pair_r_;         // m
  std::vector<double> pair_a_;         // assemble scratch: the viscous weight w_ij
  std::vector<double> pair_g_;         // dW/dr / n0, 1/m (near pairs)
  std::vector<std::int32_t> pair_bond_;  // the pair's live bond, -1 if none
  // Rows: the pairs of local particle k are near [row_near_[k], row_near_[k+1]) and far
  // [cap - row_far_[k+1], cap - row_far_[k]) (nh + 1 each).
  std::vector<std::int32_t> row_near_, row_far_;
  // The solver's compact copy of each pair (direction and density gradient first, so one
  // 16-byte load gives both to the 4-lane apply; then the second end and coefficient).
  struct PairKernel {
    float nx, ny, nz;
    float g;  // dW/dr / n0 (near pairs), 0 for far ones
    std::int32_t j;
    float a;  // dt c_ij (+ dt^2 k)
  };
  std::vector<PairKernel> kernel_;
  std::vector<float> pair_dn_;  // apply scratch: n . (x_j - x_i) of the near pairs
  // apply scratch, 4 single-precision lanes per particle (x, y, z, 0): its input and the pair
  // part of its output (nl each), and the pair divergences (nl).
  typedef float F4 __attribute__((vector_size(16)));
  std::vector<F4> apply_x_, apply_y_;
  std::vector<float> apply_s_;
  std::size_t pair_cap_ = 0;
  std::size_t near_ = 0, near_awake_ = 0, far_ = 0, far_awake_ = 0;
  std::size_t pairs_ = 0;

  // ---- Per-particle step data, local numbering ----
  std::vector<double> second_moment_;  // nh: sum w r^2 incl. walls, m^2
  std::vector<double> density_;        // nh: number density sum incl. walls (kernel units)
  std::vector<double> constraint_;     // nh: C_i = density/n0 - 1
  std::vector<double> press_coef_;     // nl: dt^2 kappa V if pressure active, else 0
  std::vector<double> visc_coef_;      // nl: 2 mu V s0 / (t0 S_i): viscous coefficient, N s/m
  std::vector<double> s_pf_;           // nl: assemble scratch, dt kappa V max(C, 0)
  std::vector<double> s_hv_;           // nl: assemble scratch, dt visc_coef / 2
  std::vector<double> mass_l_;         // na: kg
  std::vector<Vec3> rhs_;              // na
  std::vector<std::array<double, 6>> diag_inv_;  // na: inverse diagonal block (xx yy zz xy xz yz)
  std::vector<Vec3> vel_;              // nl: velocities being solved for, m/s
  std::vector<Vec3> r_, z_, p_, q_;    // solver vectors
  std::vector<double> s_;              // nl: divergence scratch
  // Particles with walls (local index), their no-slip tensor dt * C_w and density gradient.
  std::vector<std::int32_t> wall_particle_;
  std::vector<Eigen::Matrix3d> wall_c_;
  std::vector<Vec3> wall_g_;           // gradient of the wall density term / n0, 1/m
  std::vector<std::int32_t> wall_slot_;  // nh: index into wall_particle_, -1 if none
  std::size_t wall_particles_ = 0;
  // Particles with contact constraints (local index), filter directions and target.
  std::vector<std::int32_t> con_particle_;
  std::vector<std::uint8_t> con_count_;     // 1..3 constrained directions
  std::vector<std::array<Vec3, 3>> con_e_;  // orthonormal constrained directions
  std::vector<Vec3> con_v_;                 // constrained velocity component, m/s
  std::vector<std::int32_t> con_slot_;      // na: index into con_particle_, -1 if none
  std::vector<Vec3> con_av_;                // (A v) at the constrained particles, N s
  std::vector<Vec3> con_aq_;                // scratch: (A p) there before the filter
  std::size_t con_particles_ = 0;
  // Collider culling for the contact projection: colliders whose surface was within the wall
  // range of the particle at the start of the step (bit k for collider k, statics first).
  std::vector<std::uint32_t> near_colliders_;  // na
  std::vector<std::uint8_t> all_colliders_;    // na: 1 = check every collider
  // Static colliders that may be within the wall range of a particle (bit k for static k),
  // found at static_ref_ and valid while the particle stays within kStaticMaskMargin h of it
  // (setup_walls). N each; static_ref_ starts as NaN (no mask yet).
  std::vector<Vec3> static_ref_;
  std::vector<std::uint32_t> static_mask_;

  // Wall interactions (capacity W): a particle near a collider.
  struct WallHit {
    std::int32_t particle;  // local index
    std::int32_t collider;  // index into moving (>= 0) or -1 - index into statics
    Vec3 grad;              // gradient of the solid's density share / n0, 1/m
    Eigen::Matrix3d visc;   // no-slip coupling tensor in units of the viscous coefficient
    Vec3 normal;            // outward surface normal
    Vec3 v_wall;            // surface velocity, m/s
    Vec3 point;             // surface point, m
    double distance;        // signed distance at the start of the step, m
    bool contact;           // a velocity constraint in the solve
  };
  std::vector<WallHit> walls_;
  // Collider site sums (see SolverConfig::wall_sum_cache): per particle up to
  // kMaxWallHitsPerParticle entries, each valid while the particle's place relative to its
  // collider stays within the tolerance.
  struct SiteSums {
    std::int32_t collider = -1;  // collider index (statics, then moving), -1: empty
    Vec3 local = Vec3::Zero();   // particle in the collider's frame when computed, m
    Quat orientation = Quat::Identity();  // collider orientation when computed
    double n = 0.0;              // density share
    double s2 = 0.0;             // second-moment share, m^2
    Vec3 grad = Vec3::Zero();    // density gradient share, 1/m
    Eigen::Matrix3d visc = Eigen::Matrix3d::Zero();  // no-slip tensor
  };
  std::vector<SiteSums> site_cache_;         // kMaxWallHitsPerParticle x N
  std::vector<std::uint8_t> site_cache_next_;  // N, entry to replace next
  std::size_t wall_count_ = 0;
  // Per collider of this step (statics, then moving; see collider_frames): its speeds (m/s,
  // rad/s), 1 if unrotated, and the lattice site offsets in its frame (32 x sites).
  std::array<double, 32> frame_lin_speed_{}, frame_ang_speed_{};
  std::array<std::uint8_t, 32> frame_identity_{};
  std::vector<Vec3> site_local_;
  double cache_turn_cos_ = 1.0;  // cos of half the wall-sum cache's turn limit
  static constexpr int kMaxMoving = 16;
  std::array<Pose, kMaxMoving> end_pose_;  // moving collider poses at the end of the step
  std::array<std::uint8_t, kMaxMoving> end_identity_{};  // 1: that end pose is unrotated
};

}  // namespace acdr
