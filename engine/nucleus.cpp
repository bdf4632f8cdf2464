// Nucleus solver: one linearised backward-Euler step per tick for all particle velocities.
//
// Why this scheme. At h = 1 mm and mu = 250 Pa s an explicit viscous step must be ~0.5 us
// (Morris limit, REFERENCES.md Numerics) and a k = 5 N/m lattice of 1 mg particles has
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
// continuum limit is the Newtonian stress tau = mu du/dy (seed Eq. 2-3): for a neighbourhood
// with isotropic directions, <n_x^2 n_y^2> = 1/15, which gives
//   c_ij = 30 mu V / S,   S = sum_j r_ij^2 over the neighbourhood,
// i.e. c = mu h on the 18-neighbour cubic lattice, where the form reproduces Couette flow
// exactly (the fourth moment of that lattice is isotropic). Solid walls add the missing
// half-space of neighbours as a no-slip coupling c_w = mu A / d toward the wall velocity
// (A = h^2, d = distance to the surface), so a lattice between two walls reproduces
// F = mu A U / H with H counted from wall to wall.
//
// Pressure. A lattice of repulsive springs is a solid: it carries shear at rest, so its
// stress under gravity is not hydrostatic and buoyancy comes out wrong. Instead the pressure
// comes from a density constraint C_i = n_i / n0 - 1 (n_i a kernel-weighted neighbour count,
// compression only) with energy sum 1/2 kappa V C_i^2, the position-based-fluids constraint
// of Macklin & Mueller (SIGGRAPH 2013) taken as a stiff implicit energy. Its stress is a scalar
// per particle, so at rest the material is a fluid with isotropic (hydrostatic) pressure up to
// O(strain). Its Gauss-Newton Hessian kappa V grad C grad C^T is applied matrix-free by a
// divergence pass and a gradient pass. Walls contribute the density of the missing lattice
// half-space (the idea of boundary particles of Akinci et al., SIGGRAPH 2012, here as a
// closed lattice sum), so particles resting at h/2 from a wall are at rest density.
//
// Bonds: springs k (|r| - L) along the bond; only their axial stiffness k n n^T enters K (the
// transverse geometric term is indefinite under compression). A bond breaks when its force
// k |stretch| exceeds k delta_max (seed Eq. 9-10).
//
// Contact: particles keep a distance h/2 from every collider. Inside the solve this is a
// velocity constraint along the surface normal; afterwards every particle path is swept in the
// collider's own frame from its start-of-step to its end-of-step pose, so a thin blade moving
// a millimetre per step cannot jump over a particle (the exit side is the side it came from).
#include "engine/nucleus.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>

#include "engine/state_hash.hpp"

namespace acdr {
namespace {

constexpr int kCalmStepsToSleep = 20;   // steps below the sleep speed before sleeping
constexpr int kMaxWallHitsPerParticle = 4;
constexpr double kMaxSpeed_m_s = 100.0;  // above this a particle is reported as a blow-up

/// Density kernel w(r) = (1 - r^2/R^2)^3 (the poly6 shape, Mueller et al. SCA 2003), w(0) = 1.
inline double kernel(double r, double R) {
  if (r >= R) return 0.0;
  const double q = 1.0 - r * r / (R * R);
  return q * q * q;
}
/// dw/dr.
inline double kernel_slope(double r, double R) {
  if (r >= R) return 0.0;
  const double q = 1.0 - r * r / (R * R);
  return -6.0 * r / (R * R) * q * q;
}

/// Weight of a pair in the viscous operator: (1 - r/R)^1.5 on R = 2.1 h. Chosen (by lattice
/// sums, docs/verification.md) so that the effective viscosity hardly depends on how the
/// lattice is sheared: layers sliding past each other by any fraction of h change it by
/// 0..+3.4 % (the sharp 18-neighbour stencil, exact at rest, loses up to 45 % when a neighbour
/// shell leaves the cut-off), while staying within 7 % of isotropic on the cubic lattice.
inline double viscous_weight(double r, double R) {
  if (r >= R) return 0.0;
  const double q = 1.0 - r / R;
  return q * std::sqrt(q);
}

/// Smooth occupancy of a lattice site by a solid from its signed distance: 1 a half spacing
/// inside, 0 a half spacing outside, smoothstep between (zero slope at both ends, so a
/// particle resting at the contact distance feels no jump in stiffness).
inline double occupancy(double sd, double h, double* slope) {
  const double t = std::clamp(0.5 - sd / h, 0.0, 1.0);
  if (slope) *slope = (t <= 0.0 || t >= 1.0) ? 0.0 : 6.0 * t * (1.0 - t) * (-1.0 / h);
  return t * t * (3.0 - 2.0 * t);
}

/// Pose advanced by a constant velocity over dt.
Pose advance(const Pose& p, const Vec3& v, const Vec3& w, double dt) {
  Pose out = p;
  out.position = p.position + v * dt;
  const double angle = w.norm() * dt;
  if (angle > 0.0) {
    out.orientation = Quat(Eigen::AngleAxisd(angle, w.normalized())) * p.orientation;
    out.orientation.normalize();
  }
  return out;
}

inline bool finite(const Vec3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

}  // namespace

// ------------------------------------------------------------------------------------------
// Construction

Nucleus::Nucleus(const NucleusConfig& config, const SolverConfig& solver,
                 const Vec3& gravity_m_s2, std::span<const Collider> static_colliders,
                 const NucleusOptions& options)
    : config_(config), solver_(solver), options_(options), gravity_(gravity_m_s2) {
  h_ = config.spacing_m;
  const double contact = options.contact_radius_factor * h_;
  // Lattice points at min + (i + 1/2) h: a block that fills a box touches its walls at h/2.
  NucleusParticleSetup setup;
  for (const auto& block : config.blocks) {
    Eigen::Vector3i n;
    for (int a = 0; a < 3; ++a)
      n[a] = std::max(1, static_cast<int>(std::lround((block.max_m[a] - block.min_m[a]) / h_)));
    for (int k = 0; k < n.z(); ++k)
      for (int j = 0; j < n.y(); ++j)
        for (int i = 0; i < n.x(); ++i) {
          const Vec3 p = block.min_m + h_ * Vec3(i + 0.5, j + 0.5, k + 0.5);
          bool inside = false;
          for (const auto& c : static_colliders)
            if (signed_distance(c, p, nullptr) < 0.5 * contact) inside = true;
          if (inside) continue;
          setup.positions_m.push_back(p);
          setup.materials.push_back(static_cast<std::uint8_t>(block.material));
        }
  }
  // Bonds between lattice neighbours closer than bond_radius_factor * h (brute force over a
  // temporary grid; construction only).
  const std::size_t n = setup.positions_m.size();
  const double bond_r = config.bond_radius_factor * h_;
  NeighborGrid grid;
  grid.reserve(n);
  grid.build(setup.positions_m, bond_r, {false, false, false}, Vec3::Zero(), Vec3::Zero());
  std::vector<MaterialConfig> mats = config.materials;
  if (mats.empty()) mats.emplace_back();
  if (options.bonds_enabled) {
    for (std::size_t i = 0; i < n; ++i)
      grid.for_each_candidate(i, [&](std::size_t j) {
        if (j <= i) return;
        if ((setup.positions_m[j] - setup.positions_m[i]).norm() >= bond_r) return;
        const auto& a = mats[std::min<std::size_t>(setup.materials[i], mats.size() - 1)];
        const auto& b = mats[std::min<std::size_t>(setup.materials[j], mats.size() - 1)];
        // A bond between two materials is as weak as the weaker one (the interface tears).
        NucleusParticleSetup::Bond bond;
        bond.i = static_cast<int>(i);
        bond.j = static_cast<int>(j);
        bond.stiffness_N_m = std::min(a.bond_stiffness_N_m, b.bond_stiffness_N_m);
        bond.break_stretch_m = std::min(a.bond_break_m, b.bond_break_m);
        if (bond.stiffness_N_m > 0.0) setup.bonds.push_back(bond);
      });
  }
  init(static_colliders, setup);
}

Nucleus::Nucleus(const NucleusConfig& config, const SolverConfig& solver,
                 const Vec3& gravity_m_s2, std::span<const Collider> static_colliders,
                 const NucleusParticleSetup& setup, const NucleusOptions& options)
    : config_(config), solver_(solver), options_(options), gravity_(gravity_m_s2) {
  h_ = config.spacing_m;
  NucleusParticleSetup copy = setup;
  if (!options.bonds_enabled) copy.bonds.clear();
  init(static_colliders, copy);
}

void Nucleus::init(std::span<const Collider> static_colliders,
                   const NucleusParticleSetup& setup) {
  assert(h_ > 0.0 && "nucleus spacing must be positive");
  statics_.assign(static_colliders.begin(), static_colliders.end());
  if (config_.materials.empty()) config_.materials.emplace_back();
  volume_ = h_ * h_ * h_;
  radius_ = options_.neighbor_radius_factor * h_;
  density_radius_ = std::min(options_.density_radius_factor * h_, radius_);
  contact_ = options_.contact_radius_factor * h_;

  // Rest sums of the full cubic lattice: the normalisations n0 (density) and s0 (viscosity).
  n0_ = 1.0;
  s0_ = 0.0;
  t0_ = 0.0;
  site_offset_.clear();
  site_w_.clear();
  site_r2_.clear();
  site_wv_.clear();
  site_len_.clear();
  const int m = static_cast<int>(std::ceil(options_.neighbor_radius_factor));
  for (int a = -m; a <= m; ++a)
    for (int b = -m; b <= m; ++b)
      for (int c = -m; c <= m; ++c) {
        if (a == 0 && b == 0 && c == 0) continue;
        const double r = h_ * std::sqrt(double(a * a + b * b + c * c));
        if (r >= radius_) continue;
        const double wv = viscous_weight(r, radius_);
        n0_ += kernel(r, density_radius_);
        s0_ += wv * r * r;
        t0_ += wv * (a * h_) * (a * h_) * (c * h_) * (c * h_) / (r * r);
        site_offset_.push_back(h_ * Vec3(a, b, c));
        site_w_.push_back(kernel(r, density_radius_));
        site_wv_.push_back(wv);
        site_r2_.push_back(r * r);
        site_len_.push_back(r);
      }

  build_wall_table();

  const std::size_t n = setup.positions_m.size();
  x_ = setup.positions_m;
  v_.assign(n, Vec3::Zero());
  if (setup.velocities_m_s.size() == n) v_ = setup.velocities_m_s;
  x_start_ = x_;
  f_ext_.assign(n, Vec3::Zero());
  fixed_v_.assign(n, Vec3::Zero());
  material_.assign(n, 0);
  if (setup.materials.size() == n) material_ = setup.materials;
  fixed_.assign(n, 0);
  if (setup.fixed.size() == n) fixed_ = setup.fixed;
  mass_.resize(n);
  mu_.resize(n);
  kappa_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    material_[i] = static_cast<std::uint8_t>(
        std::min<std::size_t>(material_[i], config_.materials.size() - 1));
    const MaterialConfig& mat = config_.materials[material_[i]];
    mass_[i] = mat.density_kg_m3 * volume_;
    mu_[i] = mat.viscosity_Pa_s;
    kappa_[i] = mat.bulk_modulus_Pa;
  }
  awake_.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) awake_[i] = fixed_[i] ? 0 : 1;
  halo_.assign(n, 0);
  wake_next_.assign(n, 0);
  calm_.assign(n, 0);
  active_.assign(n, 0);

  const std::size_t nb = setup.bonds.size();
  bond_ij_.resize(2 * nb);
  bond_rest_.resize(nb);
  bond_k_.resize(nb);
  bond_break_.resize(nb);
  bond_alive_.assign(nb, 1);
  bond_n_.assign(nb, Vec3::Zero());
  bond_a_.assign(nb, 0.0);
  for (std::size_t b = 0; b < nb; ++b) {
    const auto& bond = setup.bonds[b];
    assert(bond.i >= 0 && bond.j >= 0 && std::size_t(bond.i) < n && std::size_t(bond.j) < n);
    bond_ij_[2 * b] = bond.i;
    bond_ij_[2 * b + 1] = bond.j;
    bond_rest_[b] = bond.rest_length_m >= 0.0 ? bond.rest_length_m
                                              : (x_[bond.j] - x_[bond.i]).norm();
    bond_k_[b] = bond.stiffness_N_m;
    bond_break_[b] = bond.break_stretch_m;
  }

  // Fixed capacities: nothing below allocates during step().
  grid_.reserve(std::max<std::size_t>(n, 1));
  const std::size_t pair_cap = std::max<std::size_t>(16, n * options_.max_neighbors / 2);
  pair_ij_.resize(2 * pair_cap);
  pair_n_.resize(pair_cap);
  pair_r_.resize(pair_cap);
  pair_visc_.resize(pair_cap);
  pair_bond_.resize(pair_cap);
  far_ij_.resize(2 * pair_cap);
  far_n_.resize(pair_cap);
  far_r_.resize(pair_cap);
  far_bond_.resize(pair_cap);
  skin_ = options_.skin_factor * h_;
  {
    // Candidates within R + skin: the lattice count within that reach, with room for 50 %
    // compression of the neighbourhood.
    std::size_t lattice = 0;
    const double reach = options_.neighbor_radius_factor + options_.skin_factor;
    const int m = static_cast<int>(std::ceil(reach));
    for (int a = -m; a <= m; ++a)
      for (int b = -m; b <= m; ++b)
        for (int c = -m; c <= m; ++c)
          if (a * a + b * b + c * c > 0 && a * a + b * b + c * c < reach * reach) ++lattice;
    const std::size_t cand_cap = std::max<std::size_t>(16, n * lattice * 3 / 4);
    cand_ij_.resize(2 * cand_cap);
    cand_bond_.resize(cand_cap);
  }
  x_built_.assign(n, Vec3::Zero());
  candidates_valid_ = false;
  bond_in_pair_.assign(nb, 0);
  loose_.assign(nb, 0);
  // Bonds of each particle (CSR), to find a pair's bond.
  bond_adj_start_.assign(n + 1, 0);
  for (std::size_t b = 0; b < nb; ++b) {
    ++bond_adj_start_[bond_ij_[2 * b] + 1];
    ++bond_adj_start_[bond_ij_[2 * b + 1] + 1];
  }
  for (std::size_t i = 0; i < n; ++i) bond_adj_start_[i + 1] += bond_adj_start_[i];
  bond_adj_.assign(2 * nb, 0);
  {
    std::vector<std::int32_t> cursor(bond_adj_start_.begin(), bond_adj_start_.end() - 1);
    for (std::size_t b = 0; b < nb; ++b) {
      bond_adj_[cursor[bond_ij_[2 * b]]++] = static_cast<std::int32_t>(b);
      bond_adj_[cursor[bond_ij_[2 * b + 1]]++] = static_cast<std::int32_t>(b);
    }
  }
  pair_g_.resize(pair_cap);
  second_moment_.assign(n, 0.0);
  density_.assign(n, 0.0);
  constraint_.assign(n, 0.0);
  press_coef_.assign(n, 0.0);
  pressure_.assign(n, 0.0);
  body_force_.assign(n, Vec3::Zero());
  wall_c_.assign(n, Eigen::Matrix3d::Zero());
  visc_coef_.assign(n, 0.0);
  wall_g_.assign(n, Vec3::Zero());
  rhs_.assign(n, Vec3::Zero());
  diag_inv_.assign(n, Eigen::Matrix3d::Identity());
  con_count_.assign(n, 0);
  con_e_.assign(n, {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()});
  con_v_.assign(n, Vec3::Zero());
  release_.assign(n, 0);
  walls_.resize(kMaxWallHitsPerParticle * n + 16);
  r_.assign(n, Vec3::Zero());
  z_.assign(n, Vec3::Zero());
  p_.assign(n, Vec3::Zero());
  q_.assign(n, Vec3::Zero());
  s_.assign(n, 0.0);
}

// ------------------------------------------------------------------------------------------
// Accessors

std::size_t Nucleus::particle_count() const { return x_.size(); }
std::span<const Vec3> Nucleus::positions() const { return x_; }
std::span<const Vec3> Nucleus::velocities() const { return v_; }
std::span<const std::uint8_t> Nucleus::materials() const { return material_; }
double Nucleus::particle_volume_m3() const { return volume_; }
std::size_t Nucleus::bond_count() const { return bond_rest_.size(); }
std::size_t Nucleus::broken_bond_count() const { return broken_; }
std::size_t Nucleus::active_count() const { return active_count_; }
const NucleusConfig& Nucleus::config() const { return config_; }
std::span<const double> Nucleus::masses() const { return mass_; }
std::span<Vec3> Nucleus::external_forces() { return f_ext_; }
std::span<const double> Nucleus::pressures() const { return pressure_; }
std::span<const Vec3> Nucleus::body_forces() const { return body_force_; }
std::span<const std::uint8_t> Nucleus::bond_alive() const { return bond_alive_; }
std::span<const std::int32_t> Nucleus::bond_particles() const { return bond_ij_; }
void Nucleus::set_fixed_velocity(std::size_t i, const Vec3& v) { fixed_v_[i] = v; }
void Nucleus::set_gravity(const Vec3& g) { gravity_ = g; }
std::size_t Nucleus::pair_count() const { return pairs_; }

double Nucleus::kinetic_energy_J() const {
  double e = 0.0;
  for (std::size_t i = 0; i < x_.size(); ++i) e += 0.5 * mass_[i] * v_[i].squaredNorm();
  return e;
}

double Nucleus::mechanical_energy_J() const {
  double e = kinetic_energy_J();
  for (std::size_t i = 0; i < x_.size(); ++i) {
    e -= mass_[i] * gravity_.dot(x_[i]);
    if (kappa_[i] > 0.0) e += 0.5 * volume_ * pressure_[i] * pressure_[i] / kappa_[i];
  }
  for (std::size_t b = 0; b < bond_alive_.size(); ++b) {
    if (!bond_alive_[b]) continue;
    const double stretch =
        min_image(x_[bond_ij_[2 * b + 1]] - x_[bond_ij_[2 * b]]).norm() - bond_rest_[b];
    e += 0.5 * bond_k_[b] * stretch * stretch;
  }
  return e;
}
double Nucleus::spacing_m() const { return h_; }

std::uint64_t Nucleus::state_hash() const {
  std::uint64_t h = kFnvOffset;
  if (!x_.empty()) {
    h = fnv1a(x_.data(), x_.size() * sizeof(Vec3), h);
    h = fnv1a(v_.data(), v_.size() * sizeof(Vec3), h);
  }
  return h;
}

Vec3 Nucleus::min_image(const Vec3& d) const {
  Vec3 out = d;
  for (int a = 0; a < 3; ++a) {
    if (!options_.periodic[a]) continue;
    const double L = options_.periodic_max_m[a] - options_.periodic_min_m[a];
    out[a] -= L * std::round(out[a] / L);
  }
  return out;
}

// ------------------------------------------------------------------------------------------
// The step

void Nucleus::step(double dt, std::span<const Collider> moving,
                   std::span<BodyReaction> reactions, NumericalReport& report) {
  report = NumericalReport{};
  assert(moving.size() <= std::size_t(kMaxMoving) && "too many moving colliders");
  assert(dt > 0.0);
  for (auto& r : reactions) {
    r.force_N = Vec3::Zero();
    r.torque_Nm = Vec3::Zero();
    r.drag_Ns_m = 0.0;
    r.rot_drag_Nms = 0.0;
  }
  if (x_.empty()) return;
  for (std::size_t m = 0; m < moving.size(); ++m)
    end_pose_[m] = advance(moving[m].pose, moving[m].linear_velocity_m_s,
                           moving[m].angular_velocity_rad_s, dt);
  std::copy(x_.begin(), x_.end(), x_start_.begin());
  std::fill(body_force_.begin(), body_force_.end(), Vec3::Zero());

  wake_and_sleep(moving, dt);
  build_pairs();
  if (pairs_overflow_) {
    report.ok = false;
    report.stage = "neighbors";
  }
  setup_walls(dt, moving);
  assemble(dt);
  solve(report);
  for (std::size_t k = 0; k < active_count_; ++k) {
    const Vec3& v = v_[active_[k]];
    if (!finite(v)) {
      if (report.ok) report.stage = "solve";
      report.ok = false;
      break;
    }
  }
  reactions_and_pressure(dt, moving, reactions);
  integrate_and_project(dt, moving, reactions);
  for (std::size_t k = 0; k < active_count_; ++k) {
    const std::size_t i = active_[k];
    if (!finite(x_[i]) || v_[i].squaredNorm() > kMaxSpeed_m_s * kMaxSpeed_m_s) {
      if (report.ok) report.stage = finite(x_[i]) ? "speed" : "integrate";
      report.ok = false;
      break;
    }
  }
  for (auto& r : reactions)
    if (!finite(r.force_N) || !finite(r.torque_Nm)) {
      if (report.ok) report.stage = "reaction";
      report.ok = false;
    }
  break_bonds();
}

// Sleep: a particle slower than sleep_speed for a while and farther than sleep_distance from
// every moving collider is frozen (kept out of the solve, acting as a fixed neighbour). It
// wakes when a moving collider comes near, an awake neighbour moves, or a bond of it breaks.
void Nucleus::wake_and_sleep(std::span<const Collider> moving, double dt) {
  const std::size_t n = x_.size();
  active_count_ = 0;
  const double slow2 = solver_.sleep_speed_m_s * solver_.sleep_speed_m_s;
  for (std::size_t i = 0; i < n; ++i) {
    if (fixed_[i]) {
      awake_[i] = 0;
      continue;
    }
    if (!solver_.sleep_enabled) {
      awake_[i] = 1;
    } else {
      bool near = false;
      for (const auto& c : moving)
        if (signed_distance(c, x_[i], nullptr) < solver_.sleep_distance_m) {
          near = true;
          break;
        }
      if (awake_[i]) {
        const bool calm = !near && v_[i].squaredNorm() < slow2;
        calm_[i] = calm ? static_cast<std::uint16_t>(std::min(calm_[i] + 1, 60000)) : 0;
        if (calm_[i] >= kCalmStepsToSleep) {
          awake_[i] = 0;
          v_[i] = Vec3::Zero();
        }
      } else if (near || wake_next_[i]) {
        awake_[i] = 1;
        calm_[i] = 0;
      }
    }
    wake_next_[i] = 0;
    if (awake_[i]) active_[active_count_++] = static_cast<std::int32_t>(i);
  }
}

// Candidate pairs (a Verlet list, Verlet 1967): every pair closer than R + skin, found on the
// hashed grid and kept until some particle has moved more than skin / 2 since, so no pair
// within R can be missing. Rebuilding costs a grid query per particle; a step between rebuilds
// only re-measures the candidates.
void Nucleus::rebuild_candidates() {
  const std::size_t n = x_.size();
  const double reach = radius_ + skin_;
  grid_.build(x_, reach, options_.periodic, options_.periodic_min_m, options_.periodic_max_m);
  const double reach2 = reach * reach;
  candidates_ = 0;
  const std::size_t cap = cand_bond_.size();
  for (std::size_t i = 0; i < n; ++i) {
    grid_.for_each_candidate(i, [&](std::size_t j) {
      if (j <= i) return;
      if (min_image(x_[j] - x_[i]).squaredNorm() >= reach2) return;
      if (candidates_ >= cap) {
        pairs_overflow_ = true;
        return;
      }
      std::int32_t bond = -1;
      for (std::int32_t k = bond_adj_start_[i]; k < bond_adj_start_[i + 1]; ++k) {
        const std::int32_t b = bond_adj_[k];
        if (bond_ij_[2 * b] + bond_ij_[2 * b + 1] == std::int32_t(i + j)) {
          bond = b;
          break;
        }
      }
      cand_ij_[2 * candidates_] = static_cast<std::int32_t>(i);
      cand_ij_[2 * candidates_ + 1] = static_cast<std::int32_t>(j);
      cand_bond_[candidates_] = bond;
      ++candidates_;
    });
  }
  std::copy(x_.begin(), x_.end(), x_built_.begin());
  candidates_valid_ = true;
}

void Nucleus::build_pairs() {
  const std::size_t n = x_.size();
  pairs_overflow_ = false;
  // Rebuild the candidates when some particle has moved more than skin / 2 since.
  bool rebuild = !candidates_valid_;
  const double half_skin2 = 0.25 * skin_ * skin_;
  for (std::size_t i = 0; i < n && !rebuild; ++i)
    rebuild = !(min_image(x_[i] - x_built_[i]).squaredNorm() < half_skin2);
  if (rebuild) rebuild_candidates();

  const double R2 = radius_ * radius_;
  std::fill(halo_.begin(), halo_.end(), 0);
  // Halo: frozen particles next to awake ones. Their density must be complete (they push on
  // the awake ones through their pressure), so their pairs are kept too.
  if (active_count_ < n) {
    for (std::size_t c = 0; c < candidates_; ++c) {
      const std::int32_t i = cand_ij_[2 * c], j = cand_ij_[2 * c + 1];
      if (awake_[i] == awake_[j]) continue;
      const std::int32_t sleeper = awake_[i] ? j : i;
      if (halo_[sleeper]) continue;
      if (min_image(x_[j] - x_[i]).squaredNorm() < R2) halo_[sleeper] = 1;
    }
  }
  // Pairs closer than the density radius ("near": they carry pressure as well as viscosity)
  // come first, [0, near_pairs_); the others follow. A pair that is also a live bond records it,
  // so the solver applies both with one coefficient along the same direction.
  pairs_ = 0;
  near_pairs_ = 0;
  std::size_t far = 0;
  const std::size_t cap = pair_r_.size();
  const double Rd2 = density_radius_ * density_radius_;
  for (std::size_t b = 0; b < bond_alive_.size(); ++b) bond_in_pair_[b] = 0;
  for (std::size_t c = 0; c < candidates_; ++c) {
    const std::int32_t i = cand_ij_[2 * c], j = cand_ij_[2 * c + 1];
    if (!awake_[i] && !halo_[i] && !awake_[j] && !halo_[j]) continue;
    const Vec3 d = min_image(x_[j] - x_[i]);
    const double r2 = d.squaredNorm();
    if (r2 >= R2 || r2 <= 0.0) continue;
    if (near_pairs_ + far >= cap) {
      pairs_overflow_ = true;
      break;
    }
    std::int32_t bond = cand_bond_[c];
    if (bond >= 0 && !bond_alive_[bond]) bond = -1;
    if (bond >= 0) bond_in_pair_[bond] = 1;
    const double r = std::sqrt(r2);
    if (r2 < Rd2) {
      const std::size_t p = near_pairs_++;
      pair_ij_[2 * p] = i;
      pair_ij_[2 * p + 1] = j;
      pair_r_[p] = r;
      pair_n_[p] = d / r;
      pair_bond_[p] = bond;
    } else {
      const std::size_t p = far++;
      far_ij_[2 * p] = i;
      far_ij_[2 * p + 1] = j;
      far_r_[p] = r;
      far_n_[p] = d / r;
      far_bond_[p] = bond;
    }
  }
  pairs_ = near_pairs_ + far;
  for (std::size_t p = 0; p < far; ++p) {
    const std::size_t q = near_pairs_ + p;
    pair_ij_[2 * q] = far_ij_[2 * p];
    pair_ij_[2 * q + 1] = far_ij_[2 * p + 1];
    pair_r_[q] = far_r_[p];
    pair_n_[q] = far_n_[p];
    pair_bond_[q] = far_bond_[p];
  }
  // Bonds stretched beyond the interaction radius (possible only when delta_max > R - L) are
  // applied on their own.
  loose_bonds_ = 0;
  for (std::size_t b = 0; b < bond_alive_.size(); ++b) {
    if (!bond_alive_[b] || bond_in_pair_[b]) continue;
    const std::int32_t i = bond_ij_[2 * b], j = bond_ij_[2 * b + 1];
    if (!awake_[i] && !awake_[j]) continue;
    loose_[loose_bonds_++] = static_cast<std::int32_t>(b);
  }
  // Wake propagation for the next step: a frozen neighbour of a moving particle wakes.
  if (solver_.sleep_enabled) {
    const double slow2 = solver_.sleep_speed_m_s * solver_.sleep_speed_m_s;
    for (std::size_t p = 0; p < pairs_; ++p) {
      const std::int32_t i = pair_ij_[2 * p], j = pair_ij_[2 * p + 1];
      if (awake_[i] && !awake_[j] && !fixed_[j] && v_[i].squaredNorm() >= slow2) wake_next_[j] = 1;
      if (awake_[j] && !awake_[i] && !fixed_[i] && v_[j].squaredNorm() >= slow2) wake_next_[i] = 1;
    }
  }
}

// Walls: for each particle near a collider, the no-slip coupling, the missing density and
// second moment of the half-space behind the surface, and the contact constraint.
void Nucleus::setup_walls(double dt, std::span<const Collider> moving) {
  const std::size_t n = x_.size();
  wall_count_ = 0;
  // A lattice site within R of the particle can be inside the solid only if d < R + h/2.
  const double wall_range = radius_ + 0.5 * h_;
  const std::size_t n_static = statics_.size();
  for (std::size_t i = 0; i < n; ++i) {
    density_[i] = 0.0;
    second_moment_[i] = 0.0;
    wall_c_[i] = Eigen::Matrix3d::Zero();
    wall_g_[i] = Vec3::Zero();
    con_count_[i] = 0;
    con_v_[i] = Vec3::Zero();
    if (!awake_[i] && !halo_[i]) continue;
    int hits = 0;
    // Contact normals and target normal velocities of this particle (up to 3).
    Vec3 cn[3];
    double ct[3];
    int nc = 0;
    for (std::size_t k = 0; k < n_static + moving.size(); ++k) {
      const Collider& c = k < n_static ? statics_[k] : moving[k - n_static];
      Vec3 normal;
      const double d = signed_distance(c, x_[i], &normal);
      const Vec3 vw = k < n_static ? Vec3::Zero() : c.velocity_at(x_[i]);
      const double vn_rel = (v_[i] - vw).dot(normal);
      const double reach = contact_ + 0.1 * h_ + std::max(0.0, -vn_rel) * dt;
      if (d >= wall_range && d >= reach) continue;
      if (hits >= kMaxWallHitsPerParticle || wall_count_ >= walls_.size()) continue;
      ++hits;
      WallHit& w = walls_[wall_count_++];
      w.particle = static_cast<std::int32_t>(i);
      w.collider = k < n_static ? -1 - static_cast<std::int32_t>(k)
                                : static_cast<std::int32_t>(k - n_static);
      w.normal = normal;
      w.v_wall = vw;
      w.point = x_[i] - d * normal;
      // The solid fills the lattice sites a particle is missing near it: their density, its
      // gradient, and their second moment are counted as neighbours (the role of boundary
      // particles in Akinci et al. 2012), site by site from the signed distance, so edges,
      // corners and thin shells count what is really solid.
      //
      // No-slip: the solid's sites also enter the viscous sum, each moving with the mirrored
      // velocity v_w - (d_site / d)(v_i - v_w) of Morris, Fox & Zhu (J Comput Phys 1997), which
      // extends the particle's velocity profile linearly through the wall to the wall velocity
      // at the surface. A site's pair term then couples the particle to the wall velocity with
      // (1 + d_site / d) times its weight: the tensor `visc` (scaled by the particle's viscous
      // coefficient in assemble()). On the lattice this is mu A / d for the first layer.
      w.grad = Vec3::Zero();
      w.visc = Eigen::Matrix3d::Zero();
      int face_axis = -1;
      if (d < wall_range && flat_face(c, x_[i], d, normal, &face_axis)) {
        // An axis-aligned flat face seen by every site: the sums depend on d only (table).
        const WallTableEntry e = wall_table_at(d);
        density_[i] += e.n;
        second_moment_[i] += e.s2;
        w.grad = e.grad * normal;
        w.visc = e.visc_t * Eigen::Matrix3d::Identity();
        w.visc(face_axis, face_axis) = e.visc_n;
      } else if (d < wall_range) {
        const double d_eff = std::max(d, 0.25 * h_);
        for (std::size_t o = 0; o < site_offset_.size(); ++o) {
          // sd(site) >= d - |offset|: a site that far cannot be occupied.
          if (d - site_len_[o] >= 0.5 * h_) continue;
          const Vec3 q = x_[i] + site_offset_[o];
          Vec3 nq;
          const double sd = signed_distance(c, q, &nq);
          double slope = 0.0;
          const double occ = occupancy(sd, h_, &slope);
          if (occ <= 0.0) continue;
          density_[i] += occ * site_w_[o];
          second_moment_[i] += occ * site_wv_[o] * site_r2_[o];
          w.grad += (slope * site_w_[o] / n0_) * nq;
          const Vec3 u = site_offset_[o] / std::sqrt(site_r2_[o]);
          w.visc += (occ * site_wv_[o] * (1.0 + std::max(0.0, -sd) / d_eff)) * (u * u.transpose());
        }
      }
      wall_g_[i] += w.grad;
      // Contact constraint: approaching or resting particles within reach. The normal velocity
      // is set to what brings the particle exactly to the contact distance, or to its current
      // normal velocity if that is slower (no pull toward the wall). Penetrating particles are
      // stopped in the normal direction and pushed out by position after the solve.
      w.contact = false;
      if (awake_[i] && d < reach && vn_rel <= 1e-12 && (d < contact_ || !release_[i]) &&
          nc < 3) {
        const double approach = d > contact_ ? -(d - contact_) / dt : 0.0;
        cn[nc] = normal;
        ct[nc] = vw.dot(normal) + std::max(approach, std::min(vn_rel, 0.0));
        ++nc;
        w.contact = true;
      }
    }
    if (!awake_[i]) continue;
    release_[i] = 0;
    // Orthonormal constrained directions (Gram-Schmidt) and the constrained velocity
    // component v_c in their span with n_k . v_c = t_k.
    if (nc > 0) {
      Vec3 e[3];
      Vec3 used_n[3];
      double used_t[3];
      int ne = 0;
      for (int a = 0; a < nc; ++a) {
        Vec3 u = cn[a];
        for (int b = 0; b < ne; ++b) u -= e[b] * e[b].dot(u);
        const double len = u.norm();
        if (len < 0.2) continue;  // nearly parallel to one already taken
        e[ne] = u / len;
        used_n[ne] = cn[a];
        used_t[ne] = ct[a];
        ++ne;
      }
      Vec3 vc = Vec3::Zero();
      if (ne == 1) {
        vc = used_t[0] * used_n[0];
      } else if (ne == 2) {
        Eigen::Matrix2d G2;
        G2 << 1.0, used_n[0].dot(used_n[1]), used_n[0].dot(used_n[1]), 1.0;
        const Eigen::Vector2d a2 = G2.inverse() * Eigen::Vector2d(used_t[0], used_t[1]);
        vc = a2[0] * used_n[0] + a2[1] * used_n[1];
      } else {
        Eigen::Matrix3d G3;
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) G3(a, b) = used_n[a].dot(used_n[b]);
        const Vec3 a3 = G3.inverse() * Vec3(used_t[0], used_t[1], used_t[2]);
        vc = a3[0] * used_n[0] + a3[1] * used_n[1] + a3[2] * used_n[2];
      }
      con_count_[i] = static_cast<std::uint8_t>(ne);
      for (int a = 0; a < ne; ++a) con_e_[i][a] = e[a];
      con_v_[i] = vc;
    }
  }
}

// Whether particle x at distance d sees collider c as one axis-aligned flat face within the
// whole site neighbourhood (a half-space, or a box face far enough from the face's edges and
// thick enough), so the tabulated wall sums apply. `axis` receives the normal's axis.
bool Nucleus::flat_face(const Collider& c, const Vec3& x, double d, const Vec3& normal,
                        int* axis) const {
  const Quat& q = c.pose.orientation;
  if (std::abs(std::abs(q.w()) - 1.0) > 1e-12) return false;  // rotated
  int a = -1;
  for (int k = 0; k < 3; ++k)
    if (std::abs(std::abs(normal[k]) - 1.0) < 1e-12) a = k;
  if (a < 0) return false;
  *axis = a;
  if (c.kind == ColliderKind::kHalfSpace) return a == 2;
  if (c.kind != ColliderKind::kBox) return false;
  // The face's extent must cover every site within R (lateral margin R) and the solid must be
  // as deep as the sites reach (R - d; the few sites near the far face then differ from the
  // half-space value by at most a few percent of one site's weight).
  const Vec3 local = x - c.pose.position;
  if (d < 0.0) return false;
  for (int k = 0; k < 3; ++k) {
    if (k == a) continue;
    if (std::abs(local[k]) > c.half_extents_m[k] - radius_) return false;
  }
  return 2.0 * c.half_extents_m[a] >= radius_ - d;
}

// Wall sums of a flat face normal to +z at distance d, sampled over [-h/2, R + h/2].
void Nucleus::build_wall_table() {
  const int samples = static_cast<int>(wall_table_.size());
  const double lo = -0.5 * h_, hi = radius_ + 0.5 * h_;
  wall_table_step_ = (hi - lo) / (samples - 1);
  wall_table_lo_ = lo;
  for (int k = 0; k < samples; ++k) {
    const double d = lo + k * wall_table_step_;
    const double d_eff = std::max(d, 0.25 * h_);
    WallTableEntry e{};
    for (std::size_t o = 0; o < site_offset_.size(); ++o) {
      const double sd = d + site_offset_[o].z();
      double slope = 0.0;
      const double occ = occupancy(sd, h_, &slope);
      if (occ <= 0.0) continue;
      const Vec3 u = site_offset_[o] / site_len_[o];
      const double vw = occ * site_wv_[o] * (1.0 + std::max(0.0, -sd) / d_eff);
      e.n += occ * site_w_[o];
      e.s2 += occ * site_wv_[o] * site_r2_[o];
      e.grad += slope * site_w_[o] / n0_;
      e.visc_n += vw * u.z() * u.z();
      e.visc_t += vw * u.x() * u.x();
    }
    wall_table_[k] = e;
  }
}

Nucleus::WallTableEntry Nucleus::wall_table_at(double d) const {
  const double u = std::clamp((d - wall_table_lo_) / wall_table_step_, 0.0,
                              static_cast<double>(wall_table_.size() - 1));
  const std::size_t k = std::min(static_cast<std::size_t>(u), wall_table_.size() - 2);
  const double f = u - k;
  const WallTableEntry& a = wall_table_[k];
  const WallTableEntry& b = wall_table_[k + 1];
  return {a.n + f * (b.n - a.n), a.s2 + f * (b.s2 - a.s2), a.grad + f * (b.grad - a.grad),
          a.visc_n + f * (b.visc_n - a.visc_n), a.visc_t + f * (b.visc_t - a.visc_t)};
}

// Per-step coefficients, right-hand side and block-Jacobi preconditioner.
void Nucleus::assemble(double dt) {
  const std::size_t n = x_.size();
  const double R = radius_;
  const double Rd = density_radius_;
  // Neighbour sums: density (kernel units) and second moment.
  for (std::size_t i = 0; i < n; ++i) density_[i] += 1.0;  // self
  for (std::size_t p = 0; p < pairs_; ++p) {
    const std::int32_t i = pair_ij_[2 * p], j = pair_ij_[2 * p + 1];
    const double r = pair_r_[p];
    if (p < near_pairs_) {
      const double w = kernel(r, Rd);
      density_[i] += w;
      density_[j] += w;
      pair_g_[p] = kernel_slope(r, Rd) / n0_;
    }
    const double wv = viscous_weight(r, R);
    second_moment_[i] += wv * r * r;
    second_moment_[j] += wv * r * r;
    pair_visc_[p] = wv;
  }
  // Viscous coefficients c_ij = w_ij 2 mu V / T, with T the weighted fourth moment
  // sum w r_x^2 r_z^2 / r^2 of the neighbourhood: the stress of the pair operator under a
  // shear rate gamma is gamma T c / (2 V w), so this gives tau = mu gamma (see the file comment).
  // T is the rest lattice's t0 scaled by the particle's own weighted second moment S / s0 (for
  // isotropic directions T = S / 15), so a disordered or compressed neighbourhood is
  // normalised by what it actually holds. S is floored at 0.6 s0 so a sparse neighbourhood
  // (free surface, loose particles) does not get an unbounded coefficient.
  for (std::size_t i = 0; i < n; ++i)
    visc_coef_[i] = 2.0 * mu_[i] * volume_ * s0_ / (t0_ * std::max(second_moment_[i], 0.6 * s0_));
  // pair_visc_ becomes the pair's whole implicit coefficient: dt c_ij (+ dt^2 k of its bond).
  for (std::size_t p = 0; p < pairs_; ++p) {
    const std::int32_t i = pair_ij_[2 * p], j = pair_ij_[2 * p + 1];
    pair_visc_[p] *= dt * 0.5 * (visc_coef_[i] + visc_coef_[j]);
    const std::int32_t b = pair_bond_[p];
    if (b >= 0) pair_visc_[p] += dt * dt * bond_k_[b];
  }
  for (std::size_t k = 0; k < wall_count_; ++k) {
    const WallHit& w = walls_[k];
    wall_c_[w.particle] += (dt * visc_coef_[w.particle]) * w.visc;
  }
  // Pressure constraint C_i and which particles carry it (compression only, with a 1 % margin
  // so a particle about to be compressed is already implicit).
  for (std::size_t i = 0; i < n; ++i) {
    constraint_[i] = density_[i] / n0_ - 1.0;
    const bool in = awake_[i] || halo_[i];
    press_coef_[i] = (in && constraint_[i] > -0.01) ? dt * dt * kappa_[i] * volume_ : 0.0;
  }

  // Forces at the start of the step (into rhs_ as dt * f), then M v0.
  for (std::size_t i = 0; i < n; ++i) rhs_[i] = dt * (mass_[i] * gravity_ + f_ext_[i]);
  // Bonds: force k (r - L) along the bond (pair bonds along their pair; loose bonds cache
  // their direction and implicit coefficient dt^2 k for the solver).
  for (std::size_t p = 0; p < pairs_; ++p) {
    const std::int32_t b = pair_bond_[p];
    if (b < 0) continue;
    const Vec3 f = dt * bond_k_[b] * (pair_r_[p] - bond_rest_[b]) * pair_n_[p];
    rhs_[pair_ij_[2 * p]] += f;
    rhs_[pair_ij_[2 * p + 1]] -= f;
  }
  for (std::size_t k = 0; k < loose_bonds_; ++k) {
    const std::int32_t b = loose_[k];
    bond_a_[b] = 0.0;
    const std::int32_t i = bond_ij_[2 * b], j = bond_ij_[2 * b + 1];
    const Vec3 d = min_image(x_[j] - x_[i]);
    const double r = d.norm();
    if (r <= 0.0) continue;
    bond_n_[b] = d / r;
    bond_a_[b] = dt * dt * bond_k_[b];
    const Vec3 f = dt * bond_k_[b] * (r - bond_rest_[b]) * bond_n_[b];
    rhs_[i] += f;
    rhs_[j] -= f;
  }
  for (std::size_t p = 0; p < near_pairs_; ++p) {
    const std::int32_t i = pair_ij_[2 * p], j = pair_ij_[2 * p + 1];
    const double P = kappa_[i] * volume_ * std::max(constraint_[i], 0.0) +
                     kappa_[j] * volume_ * std::max(constraint_[j], 0.0);
    const Vec3 f = dt * P * pair_g_[p] * pair_n_[p];
    rhs_[i] += f;
    rhs_[j] -= f;
  }
  for (std::size_t i = 0; i < n; ++i) {
    rhs_[i] -= dt * kappa_[i] * volume_ * std::max(constraint_[i], 0.0) * wall_g_[i];
    rhs_[i] += mass_[i] * v_[i];
  }
  // Moving walls: no-slip drag toward the wall velocity, and the density change the wall's own
  // motion causes (s_i = press_coef * sum_w gw n.v_w, scattered through grad C).
  std::fill(s_.begin(), s_.end(), 0.0);
  for (std::size_t k = 0; k < wall_count_; ++k) {
    const WallHit& w = walls_[k];
    rhs_[w.particle] += (dt * visc_coef_[w.particle]) * (w.visc * w.v_wall);
    s_[w.particle] += w.grad.dot(w.v_wall);
  }
  for (std::size_t i = 0; i < n; ++i) {
    s_[i] *= press_coef_[i];
    rhs_[i] += s_[i] * wall_g_[i];
  }
  for (std::size_t p = 0; p < near_pairs_; ++p) {
    const std::int32_t i = pair_ij_[2 * p], j = pair_ij_[2 * p + 1];
    const Vec3 g = (s_[i] + s_[j]) * pair_g_[p] * pair_n_[p];
    rhs_[i] -= g;
    rhs_[j] += g;
  }

  // Block-Jacobi preconditioner: the 3x3 diagonal blocks of the system matrix.
  // grad_i C_i = -sum_j g_ij n_ij + wall_g_i, accumulated in q_ as scratch.
  for (std::size_t i = 0; i < n; ++i) {
    diag_inv_[i] = mass_[i] * Eigen::Matrix3d::Identity() + wall_c_[i];
    q_[i] = wall_g_[i];
  }
  for (std::size_t p = 0; p < pairs_; ++p) {
    const std::int32_t i = pair_ij_[2 * p], j = pair_ij_[2 * p + 1];
    const Vec3& nn = pair_n_[p];
    const Eigen::Matrix3d nnT = nn * nn.transpose();
    const double g = p < near_pairs_ ? pair_g_[p] : 0.0;
    diag_inv_[i] += (pair_visc_[p] + press_coef_[j] * g * g) * nnT;
    diag_inv_[j] += (pair_visc_[p] + press_coef_[i] * g * g) * nnT;
    q_[i] -= g * nn;
    q_[j] += g * nn;
  }
  for (std::size_t k = 0; k < loose_bonds_; ++k) {
    const std::int32_t b = loose_[k];
    if (bond_a_[b] == 0.0) continue;
    const std::int32_t i = bond_ij_[2 * b], j = bond_ij_[2 * b + 1];
    const Eigen::Matrix3d K = bond_a_[b] * bond_n_[b] * bond_n_[b].transpose();
    diag_inv_[i] += K;
    diag_inv_[j] += K;
  }
  for (std::size_t k = 0; k < active_count_; ++k) {
    const std::size_t i = active_[k];
    diag_inv_[i] += press_coef_[i] * q_[i] * q_[i].transpose();
    diag_inv_[i] = diag_inv_[i].inverse().eval();
  }
}

// y = A x for the system matrix A = M + dt C + dt^2 K (+ wall terms). Entries of frozen
// particles in x must be zero; y is meaningful on awake particles.
void Nucleus::apply(std::span<const Vec3> x, std::span<Vec3> y) {
  const std::size_t n = x_.size();
  auto& s = s_;
  for (std::size_t i = 0; i < n; ++i) {
    y[i] = mass_[i] * x[i] + wall_c_[i] * x[i];
    s[i] = wall_g_[i].dot(x[i]);
  }
  // Loose bonds: dt^2 k n n^T on the relative velocity (pair bonds are in the pair term).
  for (std::size_t k = 0; k < loose_bonds_; ++k) {
    const std::int32_t b = loose_[k];
    if (bond_a_[b] == 0.0) continue;
    const std::int32_t i = bond_ij_[2 * b], j = bond_ij_[2 * b + 1];
    const Vec3& nn = bond_n_[b];
    const Vec3 f = bond_a_[b] * nn.dot(x[j] - x[i]) * nn;
    y[i] -= f;
    y[j] += f;
  }
  // Viscosity and pair bonds (a n n^T on the relative velocity), and on near pairs the
  // divergence pass of the pressure.
  for (std::size_t p = 0; p < near_pairs_; ++p) {
    const std::int32_t i = pair_ij_[2 * p], j = pair_ij_[2 * p + 1];
    const Vec3& nn = pair_n_[p];
    const double dn = nn.dot(x[j] - x[i]);
    const Vec3 f = pair_visc_[p] * dn * nn;
    y[i] -= f;
    y[j] += f;
    const double div = pair_g_[p] * dn;
    s[i] += div;
    s[j] += div;
  }
  for (std::size_t p = near_pairs_; p < pairs_; ++p) {
    const std::int32_t i = pair_ij_[2 * p], j = pair_ij_[2 * p + 1];
    const Vec3& nn = pair_n_[p];
    const Vec3 f = (pair_visc_[p] * nn.dot(x[j] - x[i])) * nn;
    y[i] -= f;
    y[j] += f;
  }
  // Gradient pass: y += sum_k coef_k (grad C_k . x) grad C_k.
  for (std::size_t i = 0; i < n; ++i) {
    s[i] *= press_coef_[i];
    y[i] += s[i] * wall_g_[i];
  }
  for (std::size_t p = 0; p < near_pairs_; ++p) {
    const std::int32_t i = pair_ij_[2 * p], j = pair_ij_[2 * p + 1];
    const Vec3 g = (s[i] + s[j]) * pair_g_[p] * pair_n_[p];
    y[i] -= g;
    y[j] += g;
  }
}

}  // namespace acdr

namespace acdr {

// Removes the constrained components (Baraff & Witkin 1998 filter S).
void Nucleus::filter(std::span<Vec3> v) const {
  for (std::size_t k = 0; k < active_count_; ++k) {
    const std::size_t i = active_[k];
    for (int a = 0; a < con_count_[i]; ++a) v[i] -= con_e_[i][a] * con_e_[i][a].dot(v[i]);
  }
}

// Filtered, block-Jacobi preconditioned conjugate gradients on the awake particles, warm
// started from the previous velocities (the flow changes little between 1 ms ticks).
void Nucleus::solve(NumericalReport& report) {
  const std::size_t n = x_.size();
  // Initial guess: previous velocity with its constrained components replaced; frozen
  // particles hold still (fixed ones move at their prescribed velocity).
  for (std::size_t i = 0; i < n; ++i) {
    if (fixed_[i]) v_[i] = fixed_v_[i];
    else if (!awake_[i]) v_[i] = Vec3::Zero();
  }
  for (std::size_t k = 0; k < active_count_; ++k) {
    const std::size_t i = active_[k];
    Vec3 v = v_[i];
    for (int a = 0; a < con_count_[i]; ++a) v -= con_e_[i][a] * con_e_[i][a].dot(v);
    v_[i] = v + con_v_[i];
  }
  apply(v_, q_);
  double b_norm2 = 0.0, g_norm2 = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    r_[i] = Vec3::Zero();
    p_[i] = Vec3::Zero();
  }
  for (std::size_t k = 0; k < active_count_; ++k) {
    const std::size_t i = active_[k];
    r_[i] = rhs_[i] - q_[i];
    b_norm2 += rhs_[i].squaredNorm();
    g_norm2 += mass_[i] * mass_[i] * gravity_.squaredNorm();
  }
  filter(r_);
  // Tolerance relative to the right-hand side, but never below the weight impulse scale: at
  // rest the right-hand side cancels almost exactly and a purely relative test would ask for
  // round-off.
  const double scale = std::sqrt(std::max(b_norm2, g_norm2 * solver_.dt_s * solver_.dt_s));
  const double tol = solver_.tolerance * scale;
  double rz = 0.0;
  double r_norm = 0.0;
  for (std::size_t k = 0; k < active_count_; ++k) {
    const std::size_t i = active_[k];
    z_[i] = diag_inv_[i] * r_[i];
  }
  filter(z_);
  for (std::size_t k = 0; k < active_count_; ++k) {
    const std::size_t i = active_[k];
    p_[i] = z_[i];
    rz += r_[i].dot(z_[i]);
    r_norm += r_[i].squaredNorm();
  }
  r_norm = std::sqrt(r_norm);
  int it = 0;
  const int max_it = std::max(1, solver_.max_iterations);
  while (r_norm > tol && it < max_it) {
    apply(p_, q_);
    filter(q_);
    double pq = 0.0;
    for (std::size_t k = 0; k < active_count_; ++k) {
      const std::size_t i = active_[k];
      pq += p_[i].dot(q_[i]);
    }
    if (!(pq > 0.0)) break;  // converged to round-off (or a non-finite value, caught later)
    const double alpha = rz / pq;
    double rz_new = 0.0;
    r_norm = 0.0;
    for (std::size_t k = 0; k < active_count_; ++k) {
      const std::size_t i = active_[k];
      v_[i] += alpha * p_[i];
      r_[i] -= alpha * q_[i];
      r_norm += r_[i].squaredNorm();
    }
    r_norm = std::sqrt(r_norm);
    ++it;
    if (r_norm <= tol) break;
    for (std::size_t k = 0; k < active_count_; ++k) {
      const std::size_t i = active_[k];
      z_[i] = diag_inv_[i] * r_[i];
    }
    filter(z_);
    for (std::size_t k = 0; k < active_count_; ++k) {
      const std::size_t i = active_[k];
      rz_new += r_[i].dot(z_[i]);
    }
    const double beta = rz_new / rz;
    rz = rz_new;
    for (std::size_t k = 0; k < active_count_; ++k) {
      const std::size_t i = active_[k];
      p_[i] = z_[i] + beta * p_[i];
    }
  }
  report.iterations = it;
  report.residual = scale > 0.0 ? r_norm / scale : 0.0;
  if (!std::isfinite(r_norm)) {
    report.ok = false;
    report.stage = "solve";
  }
}

// What the particles do to the moving bodies, from the solved velocities (so the forces are
// the end-of-step implicit ones the particles felt): contact constraint forces, no-slip drag
// and the wall part of the pressure. Also the particle pressures for output.
void Nucleus::reactions_and_pressure(double dt, std::span<const Collider> moving,
                                     std::span<BodyReaction> reactions) {
  const std::size_t n = x_.size();
  // Divergence of the solved velocity (relative to moving walls): C at the end of the step is
  // C + dt * s, and the pressure kappa * that.
  for (std::size_t i = 0; i < n; ++i) s_[i] = wall_g_[i].dot(v_[i]);
  for (std::size_t k = 0; k < wall_count_; ++k) {
    const WallHit& w = walls_[k];
    s_[w.particle] -= w.grad.dot(w.v_wall);
  }
  for (std::size_t p = 0; p < near_pairs_; ++p) {
    const std::int32_t i = pair_ij_[2 * p], j = pair_ij_[2 * p + 1];
    const double div = pair_g_[p] * pair_n_[p].dot(v_[j] - v_[i]);
    s_[i] += div;
    s_[j] += div;
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (press_coef_[i] > 0.0) pressure_[i] = std::max(0.0, kappa_[i] * (constraint_[i] + dt * s_[i]));
    else if (awake_[i] || halo_[i]) pressure_[i] = 0.0;
  }
  // Contact forces: the constrained part of A v - b, divided by dt (q_ = A v).
  bool any_contact = false;
  for (std::size_t k = 0; k < wall_count_ && !any_contact; ++k) any_contact = walls_[k].contact;
  if (any_contact) apply(v_, q_);

  std::size_t k = 0;
  while (k < wall_count_) {
    // The hits of one particle are consecutive.
    const std::int32_t i = walls_[k].particle;
    std::size_t end = k;
    while (end < wall_count_ && walls_[end].particle == i) ++end;
    // Split the constraint force over this particle's contacts: lambda = sum_a a_k n_k.
    double share[kMaxWallHitsPerParticle] = {0, 0, 0, 0};
    if (awake_[i] && con_count_[i] > 0) {
      Vec3 lambda = (q_[i] - rhs_[i]) / dt;
      Vec3 constrained = Vec3::Zero();
      for (int a = 0; a < con_count_[i]; ++a)
        constrained += con_e_[i][a] * con_e_[i][a].dot(lambda);
      lambda = constrained;
      int idx[3];
      int nc = 0;
      for (std::size_t h = k; h < end && nc < 3; ++h)
        if (walls_[h].contact) idx[nc++] = static_cast<int>(h - k);
      if (nc == 1) {
        share[idx[0]] = lambda.dot(walls_[k + idx[0]].normal);
      } else if (nc > 1) {
        Eigen::Matrix3d G = Eigen::Matrix3d::Identity();
        Vec3 rhs = Vec3::Zero();
        for (int a = 0; a < nc; ++a) {
          rhs[a] = walls_[k + idx[a]].normal.dot(lambda);
          for (int b = 0; b < nc; ++b)
            G(a, b) = walls_[k + idx[a]].normal.dot(walls_[k + idx[b]].normal);
        }
        const Vec3 sol = G.ldlt().solve(rhs);
        for (int a = 0; a < nc; ++a) share[idx[a]] = std::isfinite(sol[a]) ? sol[a] : 0.0;
      }
      // A wall that pulls (negative share) lets go next step.
      for (int a = 0; a < nc; ++a)
        if (share[idx[a]] < 0.0) release_[i] = 1;
    }
    for (std::size_t h = k; h < end; ++h) {
      const WallHit& w = walls_[h];
      if (w.collider < 0) continue;
      const Collider& c = moving[w.collider];
      if (c.body < 0 || static_cast<std::size_t>(c.body) >= reactions.size()) continue;
      BodyReaction& r = reactions[c.body];
      // Force on the body = minus the force on the particle.
      Vec3 f = -share[h - k] * w.normal;                 // contact
      const Eigen::Matrix3d C = visc_coef_[i] * w.visc;
      f += C * (v_[i] - w.v_wall);                       // no-slip drag
      f += volume_ * pressure_[i] * w.grad;              // wall pressure (grad points inward)
      r.force_N += f;
      body_force_[i] += f;
      const Vec3 arm = w.point - r.reference_point;
      r.torque_Nm += arm.cross(f);
      // Trace: an upper bound of the largest eigenvalue of the (PSD) coupling tensor.
      r.drag_Ns_m += C.trace();
      r.rot_drag_Nms += C.trace() * arm.squaredNorm();
    }
    k = end;
  }
}

// Positions, then the swept contact projection: each particle path is followed in the
// collider's frame from its start-of-step pose to its end-of-step pose; a path that enters the
// (h/2-inflated) solid is stopped on the side it came from.
void Nucleus::integrate_and_project(double dt, std::span<const Collider> moving,
                                    std::span<BodyReaction> reactions) {
  const std::size_t n = x_.size();
  for (std::size_t i = 0; i < n; ++i)
    if (fixed_[i]) x_[i] += dt * fixed_v_[i];
  for (std::size_t k = 0; k < active_count_; ++k) {
    const std::size_t i = active_[k];
    x_[i] += dt * v_[i];
  }
  const std::size_t n_static = statics_.size();
  const double tiny = 1e-4 * h_;
  for (std::size_t k = 0; k < active_count_; ++k) {
    const std::size_t i = active_[k];
    // Statics, then the moving bodies, then the statics again: a particle squeezed between
    // the instrument and a wall ends on the wall's side (walls and bone are never crossed; an
    // overlap with the instrument is pushed out over the next steps).
    const std::size_t n_all = n_static + moving.size();
    for (std::size_t pass = 0; pass < n_all + (moving.empty() ? 0 : n_static); ++pass) {
      const std::size_t c_idx = pass < n_all ? pass : pass - n_all;
      const bool is_static = c_idx < n_static;
      const Collider& c = is_static ? statics_[c_idx] : moving[c_idx - n_static];
      const Pose& start = c.pose;
      const Pose& end = is_static ? c.pose : end_pose_[c_idx - n_static];
      const Vec3 p0 = start.inverse_apply(x_start_[i]);
      Vec3 p1 = end.inverse_apply(x_[i]);
      Vec3 n1;
      const double d1 = signed_distance_local(c, p1, &n1);
      Vec3 n0;
      const double d0 = signed_distance_local(c, p0, &n0);
      const double len = (p1 - p0).norm();
      // The path cannot reach the inflated surface (triangle inequality on distances).
      if (d1 >= contact_ - tiny && len <= d0 + d1 - 2.0 * contact_) continue;
      Vec3 normal;   // local normal of the face the particle is held on
      Vec3 surface;  // a local point of that face
      bool hit = false;
      if (d0 < contact_) {
        // Started in contact: the exit side is the start side.
        if (d1 >= contact_ - tiny) continue;
        normal = n0;
        surface = p0 - d0 * n0;
        hit = true;
      } else {
        // Sphere-trace the path against the inflated distance.
        const Vec3 u = (p1 - p0) / std::max(len, 1e-300);
        double t = 0.0;
        for (int it = 0; it < 64 && t < len; ++it) {
          Vec3 nn;
          const double d = signed_distance_local(c, p0 + t * u, &nn) - contact_;
          if (d < tiny) {
            normal = nn;
            surface = p0 + t * u - (d + contact_) * nn;
            hit = true;
            break;
          }
          t += d;
        }
        if (!hit) {
          if (d1 >= contact_ - tiny) continue;
          normal = n1;  // ended inside without a traced entry (grazing): use the end normal
          surface = p1 - d1 * n1;
          hit = true;
        }
      }
      // Put the particle on the entry face's plane at the contact distance, keeping its
      // tangential motion; if that is still inside (a corner), step back to the entry side.
      Vec3 q = p1 + std::max(0.0, contact_ - (p1 - surface).dot(normal)) * normal;
      Vec3 nq;
      const double dq = signed_distance_local(c, q, &nq);
      if (dq < contact_ - tiny) {
        if (dq > -contact_ && nq.dot(normal) > 0.0) q += (contact_ - dq) * nq;
        else q = surface + contact_ * normal;
      }
      x_[i] = end.apply(q);
      // Remove the approaching normal velocity relative to the surface; its impulse is a
      // force on the collider's body.
      const Vec3 nw = end.orientation * normal;
      const Vec3 vw = is_static ? Vec3::Zero() : moving[c_idx - n_static].velocity_at(x_[i]);
      const double vn = (v_[i] - vw).dot(nw);
      if (vn < 0.0) {
        v_[i] -= vn * nw;
        if (!is_static) {
          const Collider& mc = moving[c_idx - n_static];
          if (mc.body >= 0 && static_cast<std::size_t>(mc.body) < reactions.size()) {
            BodyReaction& r = reactions[mc.body];
            const Vec3 f = mass_[i] * vn / dt * nw;  // minus the particle's momentum change rate
            r.force_N += f;
            body_force_[i] += f;
            r.torque_Nm += (x_[i] - r.reference_point).cross(f);
          }
        }
      }
    }
  }
  // Periodic wrap.
  for (int a = 0; a < 3; ++a) {
    if (!options_.periodic[a]) continue;
    const double lo = options_.periodic_min_m[a];
    const double L = options_.periodic_max_m[a] - lo;
    for (std::size_t k = 0; k < active_count_; ++k) {
      const std::size_t i = active_[k];
      x_[i][a] = lo + (x_[i][a] - lo) - L * std::floor((x_[i][a] - lo) / L);
    }
  }
}

// Bonds break when their force exceeds k * delta_max, i.e. |stretch| > delta_max
// (seed Eq. 9-10).
void Nucleus::break_bonds() {
  for (std::size_t b = 0; b < bond_alive_.size(); ++b) {
    if (!bond_alive_[b] || bond_break_[b] <= 0.0) continue;
    const std::int32_t i = bond_ij_[2 * b], j = bond_ij_[2 * b + 1];
    if (!awake_[i] && !awake_[j] && !fixed_[i] && !fixed_[j]) continue;
    const double stretch = min_image(x_[j] - x_[i]).norm() - bond_rest_[b];
    if (std::abs(stretch) > bond_break_[b]) {
      bond_alive_[b] = 0;
      ++broken_;
      if (!fixed_[i]) wake_next_[i] = 1;
      if (!fixed_[j]) wake_next_[j] = 1;
    }
  }
}

}  // namespace acdr
