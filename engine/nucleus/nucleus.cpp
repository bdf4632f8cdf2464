// Nucleus solver: one linearised backward-Euler step per tick for all particle velocities.
//
// Why this scheme. At h = 1 mm and mu = 250 Pa s an explicit viscous step must be ~0.5 us
// (Morris limit, docs/references.md, Numerics) and a k = 5 N/m lattice of 1 mg particles has
// omega*dt ~ 10 at 1 ms, so every stiff part must be implicit. We take the velocity form of
// backward Euler linearised at the start of the step (Baraff & Witkin, SIGGRAPH 1998):
//
//   (M + dt C + dt^2 K) v1 = M v0 + dt f0 + (terms of moving walls)
//
// where C is the viscous operator, K the (positive semi-definite) stiffness of bonds and
// pressure, and f0 the forces at the start of the step. Backward Euler is L-stable: for any
// dt, stiffness and viscosity the linear part cannot gain energy, which is what a haptic loop
// needs. The system is symmetric positive definite and is solved matrix-free by
// preconditioned conjugate gradients, warm-started with the previous velocities, with a 3x3
// block-Jacobi preconditioner (the solver structure of Weiler, Koschier, Brand, Bender,
// "A physically consistent implicit viscosity solver for SPH fluids", CGF 2018). Contacts
// are velocity constraints inside the solve, imposed by the filtered ("modified") PCG of
// Baraff & Witkin 1998, so resting weight and wall pushes reach the instrument exactly.
//
// Viscosity. A pair form f_i = sum_j c_ij n_ij n_ij^T (v_j - v_i): central forces, so linear
// and angular momentum are conserved and a rigid rotation is not damped (the property Weiler
// et al. 2018 require of a physical viscosity). Its coefficient is calibrated so that the
// continuum limit is the Newtonian stress tau = mu du/dy (seed Eq. 2-3): under a shear rate
// gamma the pair sum carries tau = gamma c T / (2 V) with T = sum_j w_ij r_x^2 r_z^2 / r^2, so
//   c_ij = w_ij 2 mu V / T,
// T taken from the rest lattice and scaled by each particle's weighted second moment (for
// isotropic directions T = S / 15). The weights w = (1 - r/R)^1.25 on R = 1.98 h (26
// neighbours) were chosen from lattice sums: the 18-neighbour sharp stencil is exact at rest
// but loses up to 45 % of its viscosity when particle layers slide past each other; these
// weights keep it within -3.6..+0.4 % for every sliding offset (see viscous_weight_of). Solid
// walls enter the sum as lattice sites inside the solid whose velocity is mirrored through the
// wall (Morris, Fox & Zhu, J Comput Phys 1997), so a lattice between two walls reproduces
// F = mu A U / H exactly.
//
// Pressure. A lattice of repulsive springs is a solid: it carries shear at rest, so its
// stress under gravity is not hydrostatic and buoyancy comes out wrong. Instead the pressure
// comes from a density constraint C_i = n_i / n0 - 1 (n_i a kernel-weighted neighbour count,
// compression only) with energy sum 1/2 kappa V C_i^2, the position-based-fluids constraint
// of Macklin & Mueller (SIGGRAPH 2013) taken as a stiff implicit energy. Its stress is a scalar
// per particle, so at rest the material is a fluid with isotropic (hydrostatic) pressure up to
// O(strain). Its Gauss-Newton Hessian kappa V grad C grad C^T is applied matrix-free by a
// divergence pass and a gradient pass. Walls contribute the density of the lattice sites
// inside them (the idea of boundary particles of Akinci et al., SIGGRAPH 2012, here as sites
// with a smooth occupancy from the signed distance), so particles resting at h/2 from a wall,
// edge or corner are at rest density.
//
// Bonds: springs k (|r| - L) along the bond; only their axial stiffness k n n^T enters K (the
// transverse geometric term is indefinite under compression). A bond breaks when its force
// k |stretch| exceeds k delta_max (seed Eq. 9-10).
// A material may be cohesive: touching particles of it that rest relative to their neighbours
// bond again, at their current distance (nucleus_cohesion.cpp).
//
// Contact: particles keep a distance h/2 from every collider. Inside the solve this is a
// velocity constraint along the surface normal that only pushes: a contact whose force would
// pull its particle toward the wall lets go and the velocities are solved again, up to three
// solves a step (nucleus_contacts.cpp); afterwards every particle path is swept in the
// collider's own frame from its start-of-step to its end-of-step pose, so a thin blade moving
// a millimetre per step cannot jump over a particle (the exit side is the side it came from).
#include "engine/nucleus/nucleus.hpp"

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <cstdint>

#include "engine/core/state_hash.hpp"
#include "engine/nucleus/neighbor_grid.hpp"
#include "engine/nucleus/nucleus_math.hpp"
#include "engine/nucleus/nucleus_stages.hpp"
#include "engine/nucleus/surface_tension.hpp"

namespace acdr {
namespace {

constexpr double kMaxSpeed_m_s = 100.0;  // above this a particle is reported as a blow-up

// Whether an intact built bond joins particles i and j (a pair may hold more than one).
bool built_bond_joins(const NucleusModel& model, const NucleusState& state, std::int32_t i,
                      std::int32_t j) {
  const BondTable& bonds = model.bonds;
  if (bonds.adj_start.empty()) return false;
  for (std::int32_t a = bonds.adj_start[i]; a < bonds.adj_start[i + 1]; ++a) {
    const std::int32_t b = bonds.adj[a];
    if (bonds.other(b, i) == j && state.bond_alive[b]) return true;
  }
  return false;
}

// The surface tension's potential (surface_tension.hpp) summed over the pairs it acts on:
// particles of one material with a surface tension, closer than its reach, without an intact
// built bond. A diagnostic outside the step: it may allocate.
double surface_tension_energy_J(const NucleusModel& model, const NucleusState& state) {
  const double R = model.tension_reach;
  NeighborGrid grid;
  grid.reserve(state.x.size());
  grid.build(state.x, R, model.options.periodic, model.options.periodic_min_m,
             model.options.periodic_max_m);
  double e = 0.0;
  for (std::size_t i = 0; i < state.x.size(); ++i) {
    if (!(model.tension_force[i] > 0.0)) continue;
    grid.for_each_candidate(i, [&](std::size_t j) {
      if (j <= i || model.material[j] != model.material[i]) return;
      const double r = min_image(model, state.x[j] - state.x[i]).norm();
      if (!(r < R) || built_bond_joins(model, state, static_cast<std::int32_t>(i),
                                       static_cast<std::int32_t>(j)))
        return;
      e += nucleus::surface_tension_energy(r, model.h, R, model.tension_force[i]);
    });
  }
  return e;
}

}  // namespace

// ------------------------------------------------------------------------------------------
// Construction

Nucleus::Nucleus(const NucleusConfig& config, const SolverConfig& solver,
                 const Vec3& gravity_m_s2, std::span<const Collider> static_colliders,
                 const NucleusOptions& options)
    : Nucleus(config, solver, gravity_m_s2, static_colliders,
              nucleus::lattice_setup(config, options, static_colliders), options) {}

Nucleus::Nucleus(const NucleusConfig& config, const SolverConfig& solver,
                 const Vec3& gravity_m_s2, std::span<const Collider> static_colliders,
                 const NucleusParticleSetup& setup, const NucleusOptions& options) {
  model_.config = config;
  model_.solver = solver;
  model_.options = options;
  model_.gravity = gravity_m_s2;
  NucleusParticleSetup copy = setup;
  if (!options.bonds_enabled) copy.bonds.clear();
  nucleus::build_model(model_, static_colliders, copy);
  nucleus::init_state(model_, copy, state_);
  nucleus::reserve_workspace(model_, work_);
}

// ------------------------------------------------------------------------------------------
// Accessors

std::size_t Nucleus::particle_count() const { return state_.x.size(); }
std::span<const Vec3> Nucleus::positions() const { return state_.x; }
std::span<const Vec3> Nucleus::velocities() const { return state_.v; }
std::span<const std::uint8_t> Nucleus::materials() const { return model_.material; }
double Nucleus::particle_volume_m3() const { return model_.volume; }
std::size_t Nucleus::bond_count() const { return model_.bonds.size(); }
std::size_t Nucleus::broken_bond_count() const { return state_.broken_bonds; }
std::size_t Nucleus::reformed_bond_count() const { return state_.reformed.made; }
std::span<const std::int32_t> Nucleus::reformed_bond_particles() const {
  return state_.reformed.ij;
}
std::span<const std::uint8_t> Nucleus::reformed_bond_intact() const {
  return state_.reformed.alive;
}
std::size_t Nucleus::intact_reformed_bond_count() const {
  return state_.reformed.capacity() - state_.reformed.free_count;
}
std::size_t Nucleus::active_count() const { return state_.active_count; }
const NucleusConfig& Nucleus::config() const { return model_.config; }
std::span<const double> Nucleus::masses() const { return model_.mass; }
std::span<Vec3> Nucleus::external_forces() { return state_.f_ext; }
std::span<const double> Nucleus::pressures() const { return state_.pressure; }
std::span<const Vec3> Nucleus::body_forces() const { return state_.body_force; }
std::span<const Vec3> Nucleus::static_forces() const { return state_.static_force; }
std::span<const std::uint8_t> Nucleus::bond_alive() const { return state_.bond_alive; }
std::span<const std::int32_t> Nucleus::bond_particles() const { return model_.bonds.ij; }
void Nucleus::set_fixed_velocity(std::size_t i, const Vec3& v) { state_.fixed_v[i] = v; }
void Nucleus::set_gravity(const Vec3& g) { model_.gravity = g; }

bool Nucleus::is_kinematic(std::size_t i) const { return state_.kinematic[i] != 0; }

void Nucleus::forget_moving_wall_sums() {
  const auto statics = static_cast<std::int32_t>(model_.statics.size());
  for (SiteSums& e : work_.site_cache.entries)
    if (e.collider >= statics) e.collider = -1;
}

void Nucleus::set_kinematic(std::size_t i, bool kinematic) {
  NucleusState& s = state_;
  const auto id = static_cast<std::int32_t>(i);
  if (model_.fixed[i] || (s.kinematic[i] != 0) == kinematic) return;
  auto& list = s.kinematic_list;  // ascending; capacity N reserved at build
  if (kinematic) {
    s.kinematic[i] = 1;
    list.insert(std::lower_bound(list.begin(), list.end(), id), id);
    s.fixed_v[i] = s.v[i];
    if (s.awake[i]) {
      // Out of the awake list (kept ascending); the update of the Verlet rows notes its
      // displacement from now on through the kinematic list.
      s.awake[i] = 0;
      const auto first = s.active.begin();
      const auto last = first + static_cast<std::ptrdiff_t>(s.active_count);
      std::copy(std::upper_bound(first, last, id), last, std::lower_bound(first, last, id));
      --s.active_count;
    }
    s.calm[i] = 0;
    return;
  }
  s.kinematic[i] = 0;
  list.erase(std::lower_bound(list.begin(), list.end(), id));
  s.v[i] = s.fixed_v[i];
  s.fixed_v[i] = Vec3::Zero();
  // Its displacement since the rows were built stays in their rebuild test until it is awake
  // (as for a particle falling asleep, nucleus_sleep.cpp).
  VerletRows& rows = work_.rows;
  const double d2 = min_image(model_, s.x[i] - rows.x_built[i]).squaredNorm();
  if (!(d2 <= rows.frozen_disp2[1])) {
    rows.frozen_disp2[1] = d2;
    if (!(rows.frozen_disp2[1] <= rows.frozen_disp2[0]))
      std::swap(rows.frozen_disp2[0], rows.frozen_disp2[1]);
  }
  if (!s.wake_next[i]) {
    s.wake_next[i] = 1;
    s.wake_list[s.wake_count++] = id;
  }
}

Vec3 Nucleus::bond_pull_N(std::size_t i) const {
  const BondTable& bonds = model_.bonds;
  const auto id = static_cast<std::int32_t>(i);
  Vec3 f = Vec3::Zero();
  for (std::int32_t a = bonds.adj_start[i]; a < bonds.adj_start[i + 1]; ++a) {
    const std::int32_t b = bonds.adj[a];
    if (!state_.bond_alive[b]) continue;
    const Vec3 d = min_image(model_, state_.x[bonds.other(b, id)] - state_.x[i]);
    const double r = d.norm();
    if (r > 0.0) f += bonds.k[b] * (r - bonds.rest[b]) / r * d;
  }
  return f;
}
std::size_t Nucleus::pair_count() const { return work_.pairs.count; }
double Nucleus::spacing_m() const { return model_.h; }

double Nucleus::kinetic_energy_J() const {
  double e = 0.0;
  for (std::size_t i = 0; i < state_.x.size(); ++i)
    e += 0.5 * model_.mass[i] * state_.v[i].squaredNorm();
  return e;
}

double Nucleus::mechanical_energy_J() const {
  double e = kinetic_energy_J();
  for (std::size_t i = 0; i < state_.x.size(); ++i) {
    e -= model_.mass[i] * model_.gravity.dot(state_.x[i]);
    if (model_.kappa[i] > 0.0)
      e += 0.5 * model_.volume * state_.pressure[i] * state_.pressure[i] / model_.kappa[i];
  }
  const BondTable& bonds = model_.bonds;
  for (std::size_t b = 0; b < state_.bond_alive.size(); ++b) {
    if (!state_.bond_alive[b]) continue;
    const double stretch =
        min_image(model_, state_.x[bonds.ij[2 * b + 1]] - state_.x[bonds.ij[2 * b]]).norm() -
        bonds.rest[b];
    e += 0.5 * bonds.k[b] * stretch * stretch;
  }
  const ReformedBonds& reformed = state_.reformed;
  for (std::size_t s = 0; s < reformed.capacity(); ++s) {
    if (!reformed.alive[s]) continue;
    const double stretch =
        min_image(model_, state_.x[reformed.ij[2 * s + 1]] - state_.x[reformed.ij[2 * s]])
            .norm() -
        reformed.rest[s];
    e += 0.5 * reformed.k[s] * stretch * stretch;
  }
  if (model_.surface_tension) e += surface_tension_energy_J(model_, state_);
  return e;
}

void Nucleus::prepare_next_step() {
  if (!state_.x.empty()) nucleus::prepare_rows(model_, state_, work_.rows);
}

void Nucleus::reserve_rows_ahead() { nucleus::reserve_rows_ahead(model_, work_); }
bool Nucleus::begin_rows_ahead() { return nucleus::begin_rows_ahead(model_, state_, work_); }
void Nucleus::build_rows_ahead(double share) {
  nucleus::build_rows_ahead(model_, work_.ahead, share);
}
bool Nucleus::adopt_rows_ahead() { return nucleus::adopt_rows_ahead(model_, state_, work_); }
std::size_t Nucleus::rows_ahead_adopted() const { return work_.ahead.adopted; }
std::size_t Nucleus::grid_builds() const { return work_.rows.grid_builds; }

std::uint64_t Nucleus::state_hash() const {
  std::uint64_t h = kFnvOffset;
  if (!state_.x.empty()) {
    h = fnv1a(state_.x.data(), state_.x.size() * sizeof(Vec3), h);
    h = fnv1a(state_.v.data(), state_.v.size() * sizeof(Vec3), h);
  }
  return h;
}

// ------------------------------------------------------------------------------------------
// The step
//
// Performance layout. Only the particles a step needs take part in it: the awake
// ones, the halo of sleeping particles within R of them, and the outer neighbours of the
// halo, numbered compactly (local indices) so the solver's vectors are contiguous. Neighbours
// come from per-particle Verlet rows (R + skin) that are rebuilt only after two particles
// moved a skin together; pairs are split into those with an awake particle (all the solver's
// iterations need) and the rest (only for densities). Nothing here loops over all particles or
// all bonds. The stages are in nucleus_stages.hpp, one file each.

void Nucleus::step(double dt, std::span<const Collider> moving,
                   std::span<BodyReaction> reactions, NumericalReport& report) {
  report = NumericalReport{};
  assert(moving.size() <= std::size_t(kMaxMovingColliders) && "too many moving colliders");
  assert(model_.statics.size() + moving.size() <= std::size_t(kMaxStepColliders) &&
         "collider masks hold 32 colliders");
  assert(dt > 0.0);
  for (auto& r : reactions) {
    r.force_N = Vec3::Zero();
    r.torque_Nm = Vec3::Zero();
    r.drag_Ns_m = 0.0;
    r.rot_drag_Nms = 0.0;
  }
  if (state_.x.empty()) return;
  nucleus::begin_step(state_, work_, moving, dt);
  nucleus::update_verlet_grid(model_, state_, work_.rows);
  nucleus::wake_and_sleep(model_, state_, work_, moving, dt);
  nucleus::build_pairs(model_, state_, work_);
  if (work_.pairs.overflow) {
    report.ok = false;
    report.stage = "neighbors";
  }
  nucleus::collider_frames(model_, work_.frames, moving);
  nucleus::setup_walls(model_, state_, work_, dt, moving);
  nucleus::assemble(model_, state_, work_, dt);
  nucleus::solve_with_contacts(model_, state_, work_, dt, report);
  for (std::size_t k = 0; k < state_.active_count; ++k) {
    if (!nucleus::finite(state_.v[state_.active[k]])) {
      if (report.ok) report.stage = "solve";
      report.ok = false;
      break;
    }
  }
  nucleus::reactions_and_pressure(model_, state_, work_, dt, moving, reactions);
  nucleus::integrate_and_project(model_, state_, work_, dt, moving, reactions);
  for (std::size_t k = 0; k < state_.active_count; ++k) {
    const std::size_t i = state_.active[k];
    if (!nucleus::finite(state_.x[i]) ||
        state_.v[i].squaredNorm() > kMaxSpeed_m_s * kMaxSpeed_m_s) {
      if (report.ok) report.stage = nucleus::finite(state_.x[i]) ? "speed" : "integrate";
      report.ok = false;
      break;
    }
  }
  for (auto& r : reactions)
    if (!nucleus::finite(r.force_N) || !nucleus::finite(r.torque_Nm)) {
      if (report.ok) report.stage = "reaction";
      report.ok = false;
    }
  nucleus::break_bonds(model_, state_, work_);
  nucleus::reform_bonds(model_, state_, work_, dt);
}

namespace nucleus {

void begin_step(NucleusState& state, NucleusWorkspace& work, std::span<const Collider> moving,
                double dt) {
  ColliderFrames& frames = work.frames;
  for (std::size_t m = 0; m < moving.size(); ++m) {
    frames.end_pose[m] = advance(moving[m].pose, moving[m].linear_velocity_m_s,
                                 moving[m].angular_velocity_rad_s, dt);
    const Quat& q = frames.end_pose[m].orientation;
    frames.end_identity[m] = q.w() == 1.0 && q.x() == 0.0 && q.y() == 0.0 && q.z() == 0.0;
  }
  // The last step's particles leave the local numbering (and their body forces reset: only
  // they were written).
  StepParticles& step = work.step;
  for (std::size_t k = 0; k < step.outer_end; ++k) {
    state.body_force[step.global[k]] = Vec3::Zero();
    state.static_force[step.global[k]] = Vec3::Zero();
    step.local[step.global[k]] = -1;
  }
  step.awake_end = step.halo_end = step.outer_end = 0;
  work.pairs.overflow = false;
}

}  // namespace nucleus
}  // namespace acdr
