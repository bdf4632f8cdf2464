// The stages of a nucleus step, as free functions over the model (read only), the state and
// the workspace, each taking the parts it reads and writes (in the spirit of MuJoCo's
// mjModel / mjData split and Jolt's soft-body update context). Nucleus::step calls them in
// this order; the tests call them one by one to check each stage's result. Internal to
// engine/nucleus (the public face is nucleus.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "engine/geometry/collider.hpp"
#include "engine/nucleus/nucleus.hpp"
#include "engine/nucleus/nucleus_model.hpp"
#include "engine/nucleus/nucleus_options.hpp"
#include "engine/nucleus/nucleus_state.hpp"
#include "engine/nucleus/nucleus_workspace.hpp"

namespace acdr::nucleus {

// ---- Building (nucleus_init.cpp, nucleus_walls.cpp) ----

/// The particles of the configured lattice blocks, clipped by the static colliders, and the
/// bonds between lattice neighbours.
NucleusParticleSetup lattice_setup(const NucleusConfig& config, const NucleusOptions& options,
                                   std::span<const Collider> static_colliders);
/// Fills the model from config, solver, options and gravity already set in it.
void build_model(NucleusModel& model, std::span<const Collider> static_colliders,
                 const NucleusParticleSetup& setup);
/// The flat-face wall sums over the distance (part of build_model).
void build_wall_table(NucleusModel& model);
void init_state(const NucleusModel& model, const NucleusParticleSetup& setup,
                NucleusState& state);
/// The Verlet rows' capacities for n particles (part of reserve_workspace).
void reserve_rows(const NucleusModel& model, std::size_t n, VerletRows& rows);
/// Every capacity a step needs, so that a step allocates nothing.
void reserve_workspace(const NucleusModel& model, NucleusWorkspace& work);

// ---- The step, in order ----

/// The last step's particles leave the local numbering; the moving colliders' end poses.
void begin_step(NucleusState& state, NucleusWorkspace& work, std::span<const Collider> moving,
                double dt);
/// Neighbours (nucleus_neighbours.cpp): rebuilds the Verlet grid when two particles have
/// moved a skin together since its last build.
void update_verlet_grid(const NucleusModel& model, const NucleusState& state, VerletRows& rows);
/// Neighbours, between two particle steps of a multi-rate world while nothing moves: the grid
/// rebuild that the next step's update_verlet_grid would do, and the rows of the particles
/// awake now, done ahead from the same positions and bonds, so the next step finds them built
/// (the same rows, so the same bits).
void prepare_rows(const NucleusModel& model, NucleusState& state, VerletRows& rows);
/// What a Verlet row reads besides the grid: the bonds' states (a live bond wins over a
/// broken one between the same two particles), the re-formed bonds (re-bonding only) and
/// whether every particle is awake (a row's lower part is then left until a step reads it).
struct RowInputs {
  std::span<const std::uint8_t> bond_alive;
  const ReformedBonds* reformed;  // the re-formed bonds the rows carry (re-bonding only)
  bool all_awake;
};
/// The inputs of rows built from the state as it stands.
RowInputs row_inputs(const NucleusState& state);
/// Neighbours: the rows of `particles` against the grid in `rows`, those not built since its
/// last build (a row that runs out of room sets rows.overflowed_ahead).
void build_rows_of(const NucleusModel& model, const RowInputs& in, VerletRows& rows,
                   std::span<const std::int32_t> particles);
/// Neighbours: the sum of the two largest displacements since the grid build (the sleepers'
/// as they fell asleep), m; the grid is rebuilt when it reaches the skin.
double verlet_displacement_bound(const NucleusModel& model, const NucleusState& state,
                                 const VerletRows& rows);
/// A squared displacement into the two largest so far, m[0] >= m[1] (NaN counts as largest).
void note_two_largest(double d2, std::array<double, 2>& m);
/// Neighbours: a new grid at positions x (every row to be built again).
void build_verlet_grid(const NucleusModel& model, std::span<const Vec3> x, VerletRows& rows);
/// Pipelined multi-rate worlds (nucleus_rows_ahead.cpp): the next grid and rows built ahead,
/// beside the particle step in flight. Begun at a launch, when the grid in use is likely to
/// run out before the step after the next (a copy of the positions, bonds and awake list
/// taken then), built in shares while the step runs (reads only the copy), adopted at the
/// next launch when still within a skin of the positions then.
void reserve_rows_ahead(const NucleusModel& model, NucleusWorkspace& work);
bool begin_rows_ahead(const NucleusModel& model, const NucleusState& state,
                      NucleusWorkspace& work);
void build_rows_ahead(const NucleusModel& model, RowsAhead& ahead, double share);
bool adopt_rows_ahead(const NucleusModel& model, const NucleusState& state,
                      NucleusWorkspace& work);
/// Sleep and wake (nucleus_sleep.cpp): the awake list of this step.
void wake_and_sleep(const NucleusModel& model, NucleusState& state, NucleusWorkspace& work,
                    std::span<const Collider> moving, double dt);
/// Neighbours: this step's particles in local numbering, their pairs and loose bonds.
void build_pairs(const NucleusModel& model, NucleusState& state, NucleusWorkspace& work);
/// Walls (nucleus_walls.cpp): per collider its speeds and the lattice sites in its frame.
void collider_frames(const NucleusModel& model, ColliderFrames& frames,
                     std::span<const Collider> moving);
/// Walls: wall hits, wall density and second-moment sums, contact constraints.
void setup_walls(const NucleusModel& model, NucleusState& state, NucleusWorkspace& work,
                 double dt, std::span<const Collider> moving);
/// System assembly (nucleus_assembly.cpp): coefficients, right-hand side, preconditioner and
/// the solver's pair records.
void assemble(const NucleusModel& model, const NucleusState& state, NucleusWorkspace& work,
              double dt);
/// The operator (nucleus_operator.cpp): y = A x on the awake rows (all rows reached when
/// `full`). Reads the assembled system in `work`; writes only `scratch`, x and y (nl each).
void apply_operator(const NucleusWorkspace& work, ApplyScratch& scratch, const Vec3* x, Vec3* y,
                    bool full);
/// The PCG solve (nucleus_pcg.cpp): the awake particles' velocities into state.v. `resume`: a
/// solve again after contacts let go (release_pulling_contacts), from the last solve's
/// velocities and residual, without a product for the residual.
void solve_velocities(const NucleusModel& model, NucleusState& state, NucleusWorkspace& work,
                      NumericalReport& report, bool resume = false);
/// Contacts (nucleus_contacts.cpp): the contacts whose force would pull their particle
/// toward the wall let go (their constraints are rebuilt from the pushing ones); returns how
/// many. Called after a solve.
int release_pulling_contacts(NucleusWorkspace& work, double dt);
/// The solve with contacts that only push: solve_velocities, then, while contacts let go
/// (release_pulling_contacts), solve again from those velocities, three solves at most; the
/// report's iterations are the sum.
void solve_with_contacts(const NucleusModel& model, NucleusState& state, NucleusWorkspace& work,
                         double dt, NumericalReport& report);
/// Reactions and pressure (nucleus_reactions.cpp): what the particles do to the moving
/// bodies, and the particle pressures.
void reactions_and_pressure(const NucleusModel& model, NucleusState& state,
                            NucleusWorkspace& work, double dt, std::span<const Collider> moving,
                            std::span<BodyReaction> reactions);
/// Integration and projection (nucleus_integration.cpp): positions, swept contact
/// projection, periodic wrap.
void integrate_and_project(const NucleusModel& model, NucleusState& state,
                           const NucleusWorkspace& work, double dt,
                           std::span<const Collider> moving, std::span<BodyReaction> reactions);
/// Bond breaking (nucleus_bonds.cpp): bonds stretched or compressed beyond their limit break
/// and wake their particles next step.
void break_bonds(const NucleusModel& model, NucleusState& state, NucleusWorkspace& work);
/// Re-bonding (nucleus_cohesion.cpp): touching particles of a re-bonding material that have
/// rested relative to their neighbours long enough bond at their current distance.
void reform_bonds(const NucleusModel& model, NucleusState& state, NucleusWorkspace& work,
                  double dt);

// ---- Contact constraints (nucleus_contacts.cpp) ----

/// Contact slot `slot`: orthonormal constrained directions (Gram-Schmidt) of the contact
/// normals cn (those nearly parallel to or facing one taken before left out) and the
/// constrained velocity component in their span with n_a . v_c = ct[a]; nc = 0 leaves the
/// slot unconstrained. Returns the normals used (bit a: cn[a]); the caller's hits of the
/// others are not contacts.
unsigned set_contact_constraint(StepContacts& contacts, std::size_t slot, const Vec3* cn,
                                const double* ct, int nc);
/// Contact slot `slot` from the hits [w0, end) marked contact (the first three, their normals
/// and contact_target): set_contact_constraint, and the hits it leaves out are not contacts.
void constrain_contact_hits(StepContacts& contacts, std::size_t slot, WallHit* hits,
                            std::size_t w0, std::size_t end);
/// Local particle k's contact constraint force (the constrained part of A v - b, over dt)
/// split over its contact hits [w0, end): lambda = sum_a share_a n_a, into share[h - w0].
/// Returns how many shares pull (are negative).
int contact_shares(const NucleusWorkspace& work, std::int32_t k, std::size_t w0,
                   std::size_t end, double dt, double* share);

// ---- Re-formed bonds (nucleus_cohesion.cpp) ----

/// Whether bond b (an index of the pairs and rows: below B built, else re-formed) is intact.
inline bool bond_intact(const NucleusModel& model, const NucleusState& state, std::int32_t b) {
  const std::size_t nb = model.bonds.size();
  return static_cast<std::size_t>(b) < nb ? state.bond_alive[b] != 0
                                          : state.reformed.alive[b - nb] != 0;
}
/// Frees the slot of a re-formed bond that broke, and takes it out of the Verlet rows.
void release_reformed_bond(NucleusState& state, VerletRows& rows, std::int32_t slot);

}  // namespace acdr::nucleus
