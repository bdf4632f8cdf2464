// The nucleus's workspace: what the stages of a step compute and pass on to the next stage,
// with capacities fixed at build so a step allocates nothing. Only the Verlet rows, the
// wall-sum cache and the static-collider masks outlive a step (as caches; see
// nucleus_state.hpp); everything else is rebuilt by every step before it is read.
//
// Two numberings: particle indices (N particles) and this step's local indices: [0,
// awake_end) the awake particles (ascending particle index), [awake_end, halo_end) the halo
// (asleep within R of an awake one; their density must be complete), [halo_end, outer_end)
// the outer ones (neighbours of the halo, seen only through their positions and
// velocities). "nl" below is the number of local particles (at most N). P is the pair
// capacity, B the bonds, S the lattice sites within R.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/core/types.hpp"
#include "engine/nucleus/particle_grid.hpp"

namespace acdr {

/// Colliders of one step (statics, then moving) that collider bit masks can name.
constexpr int kMaxStepColliders = 32;
/// Moving colliders of one step.
constexpr int kMaxMovingColliders = 16;
/// Wall hits (and wall-sum cache entries) per particle.
constexpr int kMaxWallHitsPerParticle = 4;

/// Neighbour rows: a Verlet list (Verlet 1967) per particle. Row i holds every particle within
/// R + skin of i at the last grid build. Rows stay exact until two particles have moved a skin
/// together since that build (update_verlet_grid); then the grid is rebuilt and rows are
/// recomputed lazily, only for particles that take part in a step.
struct VerletRows {
  ParticleGrid grid;
  std::vector<Vec3> x_built;  // N, positions at the last grid build, m
  bool grid_valid = false;
  // Two largest squared displacements since the build of particles that fell asleep, m^2.
  std::array<double, 2> frozen_disp2 = {0.0, 0.0};
  // The two largest displacements since the grid build, summed (update_verlet_grid), m.
  double disp_bound = 0.0;
  std::uint32_t epoch = 0;              // grid builds so far
  std::size_t grid_builds = 0;
  std::vector<std::uint32_t> epoch_of;  // N, epoch a row was computed in (0: none)
  std::vector<std::int32_t> j;          // pool: candidate particle
  std::vector<std::int32_t> bond;       // pool: their bond (any state), -1 if none
  // N: row i's upper part (the entries with an index above i) is [start, start + upper) of the
  // pool, its lower part [lower_at, lower_at + lower_len) (right after the upper part, or
  // appended later: lower_at is -1 while a deferred lower part is not built; see ensure_row).
  // Each part is ordered inside the density radius / inside R / beyond, at the grid build.
  std::vector<std::int32_t> start, upper;
  std::vector<std::int32_t> lower_at, lower_len;
  // N: where row i's upper part's "beyond" bucket (beyond R at the build) starts (== its
  // upper count for an unordered row), and the pool's squared distances at the build (m^2,
  // ordered rows only): an entry farther than R + disp_bound then cannot be within R now.
  std::vector<std::int32_t> beyond;
  std::vector<float> r2;
  std::size_t used = 0;                     // pool entries in use since the grid build
  // A row built ahead of its step (prepare_rows) ran out of room: that step reports it.
  bool overflowed_ahead = false;
  std::vector<std::int32_t> scratch_j, scratch_bond;  // one row, for ordering it
  std::vector<float> scratch_r2;
  std::vector<std::uint8_t> scratch_bucket;
  std::vector<std::int32_t> partner_bond;   // N, scratch (-1)
};

/// This step's particles in the local numbering.
struct StepParticles {
  std::vector<std::int32_t> local;     // N: particle -> local index, -1 if not in the step
  std::vector<std::int32_t> global;    // N: local index -> particle
  std::size_t awake_end = 0, halo_end = 0, outer_end = 0;
  bool frozen_moving = false;          // a halo/outer particle is fixed and moves
  std::vector<Vec3> x_start;           // N, positions at step start (awake particles), m
};

/// The solver's compact copy of a pair (direction and density gradient first, so one 16-byte
/// load gives both to the 4-lane apply; then the second end and coefficient).
struct PairKernel {
  float nx, ny, nz;
  float g;  // dW/dr / n0 (near pairs), 0 for far ones
  std::int32_t j;
  float a;  // dt c_ij (+ dt^2 k)
};

/// Pairs of this step (capacity P). Near pairs (closer than the density radius; they carry
/// pressure too) fill [0, near) from the front, those with an awake particle first: [0,
/// near_awake). Far pairs fill [cap - far, cap) from the back, those with an awake particle
/// last: [cap - far_awake, cap). The solver's iterations need only the pairs with an awake
/// particle (the others see zero velocities).
struct PairList {
  std::vector<std::int32_t> i, j;  // P, local indices
  std::vector<Vec3> n;             // P, unit vector i -> j
  std::vector<double> r;           // P, m
  std::vector<double> wv;          // P, the viscous weight w_ij (assembly)
  std::vector<double> g;           // P, dW/dr / n0, 1/m (near pairs)
  std::vector<std::int32_t> bond;  // P, the pair's live bond, -1 if none
  // Rows: the pairs of local particle k are near [row_near[k], row_near[k+1]) and far
  // [cap - row_far[k+1], cap - row_far[k]) (halo_end + 1 each).
  std::vector<std::int32_t> row_near, row_far;
  std::vector<PairKernel> kernel;  // P
  std::size_t cap = 0;
  std::size_t near = 0, near_awake = 0, far = 0, far_awake = 0;
  std::size_t count = 0;           // pairs of the last step
  bool overflow = false;           // a row or the pairs ran out of room this step
};

/// Bonds applied on their own this step (stretched beyond R, so in no pair).
struct LooseBonds {
  std::vector<std::int32_t> bond;  // B, bond index
  std::vector<std::int32_t> ij;    // 2B, 2 per loose bond: local indices
  std::vector<Vec3> n;             // B, unit direction i -> j
  std::vector<double> a;           // B, dt^2 k, N s/m
  std::size_t count = 0;
  // B: the stamp of the last step one of whose pairs carried the bond (== `stamp`: this step's
  // pairs carry it), so no pass clears the marks between steps.
  std::vector<std::uint32_t> in_pair;
  std::uint32_t stamp = 0;
};

/// Scratch of the operator, 4 single-precision lanes per particle (x, y, z, 0).
struct ApplyScratch {
  typedef float F4 __attribute__((vector_size(16)));
  std::vector<F4> x, y;     // nl: its input and the pair part of its output
  std::vector<float> s;     // nl: the pair divergences
  std::vector<float> dn;    // P: n . (x_j - x_i) of the near pairs
};
using F4 = ApplyScratch::F4;

/// Symmetric 3x3 block stored as xx, yy, zz, xy, xz, yz.
using Sym3 = std::array<double, 6>;

/// The linear system of the step, per local particle.
struct StepSystem {
  std::vector<double> second_moment;  // nh: sum w r^2 incl. walls, m^2
  std::vector<double> density;        // nh: number density sum incl. walls (kernel units)
  std::vector<double> constraint;     // nh: C_i = density/n0 - 1
  std::vector<double> press_coef;     // nl: dt^2 kappa V if pressure active, else 0
  std::vector<double> visc_coef;      // nl: 2 mu V s0 / (t0 S_i): viscous coefficient, N s/m
  std::vector<double> press_force;    // nl: assembly scratch, dt kappa V max(C, 0)
  std::vector<double> half_visc;      // nl: assembly scratch, dt visc_coef / 2
  std::vector<double> mass;           // na: kg
  std::vector<Vec3> rhs;              // na, N s
  std::vector<Sym3> diag_inv;         // na: inverse diagonal block (xx yy zz xy xz yz)
  std::vector<double> div;            // nl: divergence scratch
};

/// The conjugate-gradient vectors (nl each).
struct PcgVectors {
  std::vector<Vec3> v;        // velocities being solved for, m/s
  std::vector<Vec3> r, z, p;  // residual, preconditioned residual, direction
  std::vector<Vec3> q;        // A p (assembly: scratch for grad C)
};

/// A particle near a collider.
struct WallHit {
  std::int32_t particle;  // local index
  std::int32_t collider;  // index into moving (>= 0) or -1 - index into statics
  Vec3 grad;              // gradient of the solid's density share / n0, 1/m
  Eigen::Matrix3d visc;   // no-slip coupling tensor in units of the viscous coefficient
  Vec3 normal;            // outward surface normal
  Vec3 v_wall;            // surface velocity, m/s
  Vec3 point;             // surface point, m
  double distance;        // signed distance at the start of the step, m
  double contact_target;  // the constrained normal velocity, m/s (when contact)
  bool contact;           // a velocity constraint in the solve
};

/// Wall interactions of this step (capacity W = kMaxWallHitsPerParticle N + 16), and per
/// particle with walls (local index) its no-slip tensor dt C_w and density gradient.
struct StepWalls {
  std::vector<WallHit> hits;        // W; a particle's hits are consecutive, by local index
  std::size_t hit_count = 0;
  std::vector<std::int32_t> particle;  // nh
  std::vector<Eigen::Matrix3d> c;      // nh, dt C_w, N s/m
  std::vector<Vec3> g;                 // nh, gradient of the wall density term / n0, 1/m
  std::vector<std::int32_t> slot;      // nh: index into particle, -1 if none
  std::size_t particles = 0;
};

/// Particles with contact constraints (local index), filter directions and target.
struct StepContacts {
  std::vector<std::int32_t> particle;
  std::vector<std::uint8_t> count;     // 1..3 constrained directions
  std::vector<std::array<Vec3, 3>> e;  // orthonormal constrained directions
  std::vector<Vec3> v;                 // constrained velocity component, m/s
  std::vector<std::int32_t> slot;      // na: index into particle, -1 if none
  std::vector<Vec3> av;                // (A v) at the constrained particles, N s
  std::vector<Vec3> aq;                // scratch: (A p) there before the filter
  std::size_t particles = 0;
};

/// Collider culling. For the contact projection: colliders whose surface was within the wall
/// range of the particle at the start of the step (bit k for collider k, statics first). For
/// the walls: static colliders that may be within the wall range of a particle (bit k for
/// static k), found at static_ref and valid while the particle stays within the mask margin of
/// it (setup_walls); static_ref starts as NaN (no mask yet).
struct ColliderCulling {
  std::vector<std::uint32_t> near_colliders;  // na
  std::vector<std::uint8_t> all_colliders;    // na: 1 = check every collider
  std::vector<Vec3> static_ref;               // N, m
  std::vector<std::uint32_t> static_mask;     // N
};

/// Collider site sums (see SolverConfig::wall_sum_cache).
struct SiteSums {
  std::int32_t collider = -1;  // collider index (statics, then moving), -1: empty
  Vec3 local = Vec3::Zero();   // particle in the collider's frame when computed, m
  Quat orientation = Quat::Identity();  // collider orientation when computed
  double n = 0.0;              // density share
  double s2 = 0.0;             // second-moment share, m^2
  Vec3 grad = Vec3::Zero();    // density gradient share, 1/m
  Eigen::Matrix3d visc = Eigen::Matrix3d::Zero();  // no-slip tensor
};

/// Per particle up to kMaxWallHitsPerParticle entries, each valid while the particle's place
/// relative to its collider stays within the tolerance.
struct SiteSumCache {
  std::vector<SiteSums> entries;   // kMaxWallHitsPerParticle x N
  std::vector<std::uint8_t> next;  // N, entry to replace next
};

/// Per collider of this step (statics, then moving; see collider_frames): its speeds (m/s,
/// rad/s), 1 if unrotated, and the lattice site offsets in its frame (32 x S); the moving
/// colliders' poses at the end of the step.
struct ColliderFrames {
  std::array<double, kMaxStepColliders> lin_speed{}, ang_speed{};
  std::array<std::uint8_t, kMaxStepColliders> identity{};
  std::vector<Vec3> site_local;
  std::array<Pose, kMaxMovingColliders> end_pose;
  std::array<std::uint8_t, kMaxMovingColliders> end_identity{};  // 1: that end pose is unrotated
};

/// Pipelined multi-rate worlds: the next grid and rows, built beside the particle step in
/// flight from a copy of the state at its launch (nucleus_rows_ahead.cpp). Empty until
/// reserved.
struct RowsAhead {
  VerletRows rows;                       // the spare, swapped with the rows in use on adoption
  std::vector<Vec3> x;                   // N, positions at the launch, m
  std::vector<std::uint8_t> bond_alive;  // B, the bonds then
  std::vector<std::int32_t> awake;       // N, the awake particles then: [0, awake_count)
  std::size_t awake_count = 0;
  std::size_t built = 0;                 // rows built so far: awake[0, built)
  bool pending = false;                  // begun, not yet adopted or dropped
  // The rebuild test's bound at the last launch, and the grid it was measured on (its build
  // count), for the bound's growth over one particle step.
  double last_bound_m = 0.0;
  std::size_t last_grid = 0;
  std::size_t adopted = 0;               // grids adopted so far
};

struct NucleusWorkspace {
  VerletRows rows;
  RowsAhead ahead;
  StepParticles step;
  PairList pairs;
  LooseBonds loose;
  ApplyScratch apply;
  StepSystem sys;
  PcgVectors pcg;
  StepWalls walls;
  StepContacts contacts;
  ColliderCulling cull;
  SiteSumCache site_cache;
  ColliderFrames frames;
  // nl, the largest squared rate at which a particle's distance to a neighbour changed this
  // step, m^2/s^2 (re-bonding only; empty otherwise)
  std::vector<double> separation_rate2;
  std::vector<std::int32_t> stamp;  // N, scratch marks (wake candidates, lower rows)
  std::int32_t stamp_value = 0;
};

}  // namespace acdr
