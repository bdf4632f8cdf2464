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
//
// Contact: particles keep a distance h/2 from every collider. Inside the solve this is a
// velocity constraint along the surface normal; afterwards every particle path is swept in the
// collider's own frame from its start-of-step to its end-of-step pose, so a thin blade moving
// a millimetre per step cannot jump over a particle (the exit side is the side it came from).
#include "engine/nucleus/nucleus.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <limits>
#include <cstring>

#include "engine/core/state_hash.hpp"

namespace acdr {
namespace {

constexpr int kCalmStepsToSleep = 20;   // steps below the sleep speed before sleeping
constexpr int kMaxWallHitsPerParticle = 4;
constexpr double kMaxSpeed_m_s = 100.0;  // above this a particle is reported as a blow-up
// A particle's static-collider mask (setup_walls) holds while it stays this close (in units
// of h) to where the mask was found.
constexpr double kStaticMaskMargin = 0.25;

/// Density kernel w(r) = (1 - r/R)^3 (the "spiky" shape of Desbrun & Gascuel 1996, used for
/// pressure by Mueller et al., SCA 2003), w(0) = 1. Its slope is steepest at r = 0, so two
/// particles pushed together are pushed apart harder the closer they are; the poly6 shape's
/// slope vanishes at r = 0 and let clumps of overlapped particles jitter at high pressure.
/// In terms of q = max(0, 1 - r/R): w = q^3, dw/dr = -3 q^2 / R.
inline double kernel_of(double q) { return q * q * q; }
inline double kernel(double r, double R) { return r >= R ? 0.0 : kernel_of(1.0 - r / R); }

/// Weight of a pair in the viscous operator: (1 - r/R)^1.25 on R = 1.98 h. Chosen by lattice
/// sums (the viscosity of the pair operator under simple shear, T / S relative to rest) so
/// that the effective viscosity hardly depends on how the lattice is sheared: layers sliding
/// past each other along an axis by any fraction of h change it by -3.6..0 %, along a face
/// diagonal by -1.6..+0.4 % (the sharp 18-neighbour stencil, exact at rest, loses up to 45 %
/// when a neighbour shell leaves the cut-off), and shear along a face diagonal is within
/// 1.2 % of shear along an axis. The earlier (1 - r/R)^1.5 on R = 2.1 h (32 neighbours; by the
/// same sums 0..+1.8 %, 6.8 %) costs a fifth more pairs; cutting that radius without a
/// flatter weight makes the operator anisotropic (R = 1.75 h: +51 % along a diagonal).
/// In terms of q = max(0, 1 - r/R): q^1.25.
inline double viscous_weight_of(double q) { return q * std::sqrt(std::sqrt(q)); }
inline double viscous_weight(double r, double R) {
  return r >= R ? 0.0 : viscous_weight_of(1.0 - r / R);
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

/// World point x in a pose's frame; `identity`: the pose is unrotated, and the rotation (exact
/// for the identity quaternion) is skipped.
inline Vec3 to_local(const Pose& pose, bool identity, const Vec3& x) {
  return identity ? Vec3(x - pose.position) : pose.inverse_apply(x);
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
          if (!block.contains(p)) continue;  // anatomy: cylinder, ring, cutout
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
  site_uu_.clear();
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
        const Vec3 u = h_ * Vec3(a, b, c) / r;
        site_uu_.push_back(u * u.transpose());
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
  wake_next_.assign(n, 0);
  calm_.assign(n, 0);
  release_.assign(n, 0);
  pressure_.assign(n, 0.0);
  body_force_.assign(n, Vec3::Zero());
  static_force_.assign(n, Vec3::Zero());
  active_.assign(n, 0);
  active_count_ = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (awake_[i]) active_[active_count_++] = static_cast<std::int32_t>(i);
  fixed_list_.clear();
  for (std::size_t i = 0; i < n; ++i)
    if (fixed_[i]) fixed_list_.push_back(static_cast<std::int32_t>(i));
  wake_list_.assign(n, 0);
  wake_count_ = 0;
  stamp_.assign(n, 0);

  const std::size_t nb = setup.bonds.size();
  bond_ij_.resize(2 * nb);
  bond_rest_.resize(nb);
  bond_k_.resize(nb);
  bond_break_.resize(nb);
  bond_alive_.assign(nb, 1);
  bond_in_pair_.assign(nb, 0);
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
  // Squared lengths at which each bond breaks (break_bonds), 0 and +inf when unbreakable.
  bond_break_hi2_.assign(nb, std::numeric_limits<double>::infinity());
  bond_break_lo2_.assign(nb, 0.0);
  for (std::size_t b = 0; b < nb; ++b) {
    if (bond_break_[b] <= 0.0) continue;
    const double hi = bond_rest_[b] + bond_break_[b], lo = bond_rest_[b] - bond_break_[b];
    bond_break_hi2_[b] = hi * hi;
    bond_break_lo2_[b] = lo > 0.0 ? lo * lo : 0.0;
  }
  periodic_ = options_.periodic[0] || options_.periodic[1] || options_.periodic[2];
  loose_possible_ = false;
  for (std::size_t b = 0; b < nb; ++b)
    if (bond_break_[b] <= 0.0 || bond_rest_[b] + bond_break_[b] >= radius_) loose_possible_ = true;
  // Bonds of each particle (CSR), in bond order.
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
  loose_.assign(nb, 0);
  loose_ij_.assign(2 * nb, 0);
  loose_n_.assign(nb, Vec3::Zero());
  loose_a_.assign(nb, 0.0);

  // Fixed capacities: nothing below allocates during step().
  skin_ = options_.skin_factor * h_;
  std::size_t lattice = 0;  // lattice sites within R + skin
  {
    const double reach = options_.neighbor_radius_factor + options_.skin_factor;
    const int mm = static_cast<int>(std::ceil(reach));
    for (int a = -mm; a <= mm; ++a)
      for (int b = -mm; b <= mm; ++b)
        for (int c = -mm; c <= mm; ++c)
          if (a * a + b * b + c * c > 0 && a * a + b * b + c * c < reach * reach) ++lattice;
  }
  grid_.reserve(std::max<std::size_t>(n, 1));
  x_built_.assign(n, Vec3::Zero());
  grid_valid_ = false;
  epoch_ = 0;
  row_epoch_.assign(n, 0);
  row_start_.assign(n, 0);
  row_len_.assign(n, 0);
  // Every particle's row once per grid build, with room for 50 % compression.
  const std::size_t row_cap = std::max<std::size_t>(64, n * (lattice * 3 / 2 + 8));
  row_j_.assign(row_cap, 0);
  row_bond_.assign(row_cap, -1);
  row_scratch_j_.assign(4 * lattice + 64, 0);
  row_scratch_b_.assign(4 * lattice + 64, 0);
  row_scratch_bucket_.assign(4 * lattice + 64, 0);
  row_scratch_r2_.assign(4 * lattice + 64, 0.0f);
  row_upper_.assign(n, 0);
  row_beyond_.assign(n, 0);
  row_r2_.assign(row_cap, 0.0f);
  row_used_ = 0;
  partner_bond_.assign(n, -1);

  local_.assign(n, -1);
  lg_.assign(n, 0);
  na_ = nh_ = nl_ = 0;
  pair_cap_ = std::max<std::size_t>(16, n * std::max<std::size_t>(options_.max_neighbors, 1) / 2);
  pair_i_.assign(pair_cap_, 0);
  pair_j_.assign(pair_cap_, 0);
  pair_n_.assign(pair_cap_, Vec3::Zero());
  pair_r_.assign(pair_cap_, 0.0);
  pair_a_.assign(pair_cap_, 0.0);
  pair_g_.assign(pair_cap_, 0.0);
  pair_bond_.assign(pair_cap_, -1);
  kernel_.assign(pair_cap_, PairKernel{0.0f, 0.0f, 0.0f, 0.0f, 0, 0.0f});
  pair_dn_.assign(pair_cap_, 0.0f);
  apply_x_.assign(n, F4{0.0f, 0.0f, 0.0f, 0.0f});
  apply_y_.assign(n, F4{0.0f, 0.0f, 0.0f, 0.0f});
  apply_s_.assign(n, 0.0f);
  row_near_.assign(n + 1, 0);
  row_far_.assign(n + 1, 0);

  second_moment_.assign(n, 0.0);
  density_.assign(n, 0.0);
  constraint_.assign(n, 0.0);
  press_coef_.assign(n, 0.0);
  visc_coef_.assign(n, 0.0);
  s_pf_.assign(n, 0.0);
  s_hv_.assign(n, 0.0);
  mass_l_.assign(n, 0.0);
  rhs_.assign(n, Vec3::Zero());
  diag_inv_.assign(n, {1, 1, 1, 0, 0, 0});
  vel_.assign(n, Vec3::Zero());
  r_.assign(n, Vec3::Zero());
  z_.assign(n, Vec3::Zero());
  p_.assign(n, Vec3::Zero());
  q_.assign(n, Vec3::Zero());
  s_.assign(n, 0.0);
  wall_particle_.assign(n, 0);
  wall_c_.assign(n, Eigen::Matrix3d::Zero());
  wall_g_.assign(n, Vec3::Zero());
  wall_slot_.assign(n, -1);
  wall_particles_ = 0;
  con_particle_.assign(n, 0);
  con_count_.assign(n, 0);
  con_e_.assign(n, {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()});
  con_v_.assign(n, Vec3::Zero());
  con_slot_.assign(n, -1);
  con_av_.assign(n, Vec3::Zero());
  con_aq_.assign(n, Vec3::Zero());
  con_particles_ = 0;
  near_colliders_.assign(n, 0);
  all_colliders_.assign(n, 0);
  static_ref_.assign(n, Vec3::Constant(std::numeric_limits<double>::quiet_NaN()));
  static_mask_.assign(n, 0);
  walls_.resize(kMaxWallHitsPerParticle * n + 16);
  site_cache_.assign(kMaxWallHitsPerParticle * n, SiteSums{});
  site_cache_next_.assign(n, 0);
  site_local_.assign(32 * site_offset_.size(), Vec3::Zero());
  cache_turn_cos_ = std::cos(0.5 * solver_.wall_sum_cache_tolerance * h_ / radius_);
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
std::span<const Vec3> Nucleus::static_forces() const { return static_force_; }
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
  if (!periodic_) return d;
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
//
// Performance layout. Only the particles a step needs take part in it: the awake
// ones, the halo of sleeping particles within R of them, and the outer neighbours of the
// halo, numbered compactly (local indices) so the solver's vectors are contiguous. Neighbours
// come from per-particle Verlet rows (R + skin) that are rebuilt only after two particles
// moved a skin together; pairs are split into those with an awake particle (all the solver's
// iterations need) and the rest (only for densities). Nothing here loops over all particles or
// all bonds.

void Nucleus::step(double dt, std::span<const Collider> moving,
                   std::span<BodyReaction> reactions, NumericalReport& report) {
  report = NumericalReport{};
  assert(moving.size() <= std::size_t(kMaxMoving) && "too many moving colliders");
  assert(statics_.size() + moving.size() <= 32 && "collider masks hold 32 colliders");
  assert(dt > 0.0);
  for (auto& r : reactions) {
    r.force_N = Vec3::Zero();
    r.torque_Nm = Vec3::Zero();
    r.drag_Ns_m = 0.0;
    r.rot_drag_Nms = 0.0;
  }
  if (x_.empty()) return;
  for (std::size_t m = 0; m < moving.size(); ++m) {
    end_pose_[m] = advance(moving[m].pose, moving[m].linear_velocity_m_s,
                           moving[m].angular_velocity_rad_s, dt);
    const Quat& q = end_pose_[m].orientation;
    end_identity_[m] = q.w() == 1.0 && q.x() == 0.0 && q.y() == 0.0 && q.z() == 0.0;
  }
  // The last step's particles leave the local numbering (and their body forces reset: only
  // they were written).
  for (std::size_t k = 0; k < nl_; ++k) {
    body_force_[lg_[k]] = Vec3::Zero();
    static_force_[lg_[k]] = Vec3::Zero();
    local_[lg_[k]] = -1;
  }
  na_ = nh_ = nl_ = 0;
  pairs_overflow_ = false;

  update_grid();
  wake_and_sleep(moving, dt);
  build_pairs();
  if (pairs_overflow_) {
    report.ok = false;
    report.stage = "neighbors";
  }
  collider_frames(moving);
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

// The grid of the Verlet rows is rebuilt once two particles together have moved a skin since
// the last build: a pair closer than R now was closer than R + |dx_i| + |dx_j| then, so no
// such pair can be missing from the rows while the two largest displacements sum to less than
// the skin (the usual test, every particle within skin / 2, is the special case of equal
// ones; this one tolerates a few fast particles among slow ones). Only awake and fixed
// particles move; those that fell asleep keep the displacement they had (frozen_disp2_).
void Nucleus::update_grid() {
  double m1 = frozen_disp2_[0], m2 = frozen_disp2_[1];  // two largest squared displacements
  auto note = [&](std::int32_t i) {
    const double d2 = min_image(x_[i] - x_built_[i]).squaredNorm();
    if (!(d2 <= m2)) {  // NaN counts as largest
      if (!(d2 <= m1)) {
        m2 = m1;
        m1 = d2;
      } else {
        m2 = d2;
      }
    }
  };
  for (std::size_t k = 0; k < active_count_; ++k) note(active_[k]);
  for (const std::int32_t i : fixed_list_) note(i);
  disp_bound_ = std::sqrt(m1) + std::sqrt(m2);
  const bool rebuild = !grid_valid_ || !(disp_bound_ < skin_);
  if (!rebuild) return;
  disp_bound_ = 0.0;
  frozen_disp2_ = {0.0, 0.0};
  grid_.build(x_, radius_ + skin_, options_.periodic, options_.periodic_min_m,
              options_.periodic_max_m);
  std::copy(x_.begin(), x_.end(), x_built_.begin());
  ++epoch_;
  row_used_ = 0;
  grid_valid_ = true;
  ++grid_builds_;
  // Re-sort the awake list by particle index (it grows by appending between builds), which
  // keeps the local numbering close to the lattice order.
  if (active_count_ > 0) {
    std::size_t n_awake = 0;
    for (std::size_t i = 0; i < x_.size(); ++i)
      if (awake_[i]) active_[n_awake++] = static_cast<std::int32_t>(i);
    active_count_ = n_awake;
  }
}

// Row i: every particle within R + skin of i at the last grid build, with the bond between
// them (-1 if none). Computed at most once per grid build, when i first takes part in a step.
void Nucleus::ensure_row(std::int32_t i) {
  if (row_epoch_[i] == epoch_) return;
  row_epoch_[i] = epoch_;
  const double reach = radius_ + skin_;
  const double reach2 = reach * reach;
  // i's bonds by partner (a live bond wins over a broken one between the same particles).
  for (std::int32_t k = bond_adj_start_[i]; k < bond_adj_start_[i + 1]; ++k) {
    const std::int32_t b = bond_adj_[k];
    const std::int32_t other = bond_ij_[2 * b] == i ? bond_ij_[2 * b + 1] : bond_ij_[2 * b];
    if (partner_bond_[other] < 0 || !bond_alive_[partner_bond_[other]]) partner_bond_[other] = b;
  }
  const std::size_t start = row_used_;
  const std::size_t cap = row_j_.size();
  const Vec3 xi = x_built_[i];
  // Each entry's ordering bucket (see below): higher index first, then lower; within each,
  // inside the density radius, inside R, then beyond (at the build positions).
  const double Rd2 = density_radius_ * density_radius_, R2 = radius_ * radius_;
  const std::size_t scratch = row_scratch_j_.size();
  std::array<std::int32_t, 7> count{};
  grid_.for_each_near(xi, [&](std::int32_t j, const Vec3& xj) {
    if (j == i) return;
    const double r2 = min_image(xj - xi).squaredNorm();
    if (!(r2 < reach2)) return;
    if (row_used_ >= cap) {
      pairs_overflow_ = true;
      return;
    }
    const int bucket = (j < i ? 3 : 0) + (r2 < Rd2 ? 0 : (r2 < R2 ? 1 : 2));
    const std::size_t c = row_used_ - start;
    if (c < scratch) {
      row_scratch_bucket_[c] = static_cast<std::uint8_t>(bucket);
      row_scratch_r2_[c] = static_cast<float>(r2);
    }
    ++count[bucket + 1];
    row_j_[row_used_] = j;
    row_bond_[row_used_] = partner_bond_[j];
    ++row_used_;
  });
  for (std::int32_t k = bond_adj_start_[i]; k < bond_adj_start_[i + 1]; ++k) {
    const std::int32_t b = bond_adj_[k];
    partner_bond_[bond_ij_[2 * b] == i ? bond_ij_[2 * b + 1] : bond_ij_[2 * b]] = -1;
  }
  const std::size_t len = row_used_ - start;
  row_start_[i] = static_cast<std::int32_t>(start);
  row_len_[i] = static_cast<std::int32_t>(len);
  // Order by bucket (stable counting sort; see row_upper_). A row longer than the scratch is
  // only split into its upper and lower parts (the ordering only saves time).
  std::int32_t upper = 0, beyond = 0;
  if (len <= scratch) {
    std::copy(row_j_.begin() + start, row_j_.begin() + row_used_, row_scratch_j_.begin());
    std::copy(row_bond_.begin() + start, row_bond_.begin() + row_used_, row_scratch_b_.begin());
    for (int b = 0; b < 6; ++b) count[b + 1] += count[b];
    upper = count[3];
    beyond = count[2];
    for (std::size_t c = 0; c < len; ++c) {
      const std::size_t at = start + count[row_scratch_bucket_[c]]++;
      row_j_[at] = row_scratch_j_[c];
      row_bond_[at] = row_scratch_b_[c];
      row_r2_[at] = row_scratch_r2_[c];
    }
  } else {
    // Unordered: upper/lower partition only (in place, order within the parts lost).
    std::size_t lo = start, hi = row_used_;
    while (lo < hi) {
      if (row_j_[lo] > i) {
        ++lo;
      } else {
        --hi;
        std::swap(row_j_[lo], row_j_[hi]);
        std::swap(row_bond_[lo], row_bond_[hi]);
      }
    }
    upper = static_cast<std::int32_t>(lo - start);
    beyond = upper;
  }
  row_upper_[i] = upper;
  row_beyond_[i] = beyond;
}

namespace {

/// World-space bounding box of a collider; false when it has none (a half-space).
bool collider_bounds(const Collider& c, Vec3* lo, Vec3* hi) {
  Vec3 e = Vec3::Zero();
  switch (c.kind) {
    case ColliderKind::kHalfSpace: return false;
    // Bone: the sampled field may be clipped to the disc space while the bone goes on beyond
    // it, so no box bounds the solid; it is tested for every particle (one trilinear lookup).
    case ColliderKind::kSdfGrid: return false;
    case ColliderKind::kBox:
      e = c.pose.orientation.toRotationMatrix().cwiseAbs() * c.half_extents_m;
      break;
    case ColliderKind::kCapsule:
      e = c.pose.orientation.toRotationMatrix().cwiseAbs() * Vec3(0, 0, c.half_length_m) +
          Vec3::Constant(c.radius_m);
      break;
    case ColliderKind::kCupShell: e = Vec3::Constant(c.radius_m); break;
  }
  *lo = c.pose.position - e;
  *hi = c.pose.position + e;
  return true;
}

/// Distance from p to the box [lo, hi] (0 inside): a lower bound of the distance to any solid
/// inside the box.
inline double box_gap2(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  return (lo - p).cwiseMax(p - hi).cwiseMax(0.0).squaredNorm();
}
inline double box_gap(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  return std::sqrt(box_gap2(p, lo, hi));
}

}  // namespace

// Sleep: a particle slower than sleep_speed for a while and farther than sleep_distance from
// every moving collider is frozen (kept out of the solve, acting as a fixed neighbour). It
// wakes when a moving collider comes near, an awake neighbour moves, or a bond of it breaks.
// Only particles that can change state are visited: the awake ones, those queued to wake, and
// those in grid cells near a moving collider.
void Nucleus::wake_and_sleep(std::span<const Collider> moving, double dt) {
  const std::size_t n = x_.size();
  if (!solver_.sleep_enabled) {
    // Everything that is not fixed is integrated (the "skip off" case).
    if (active_count_ + fixed_list_.size() != n) {
      active_count_ = 0;
      for (std::size_t i = 0; i < n; ++i) {
        awake_[i] = fixed_[i] ? 0 : 1;
        if (awake_[i]) active_[active_count_++] = static_cast<std::int32_t>(i);
      }
    }
    for (std::size_t k = 0; k < wake_count_; ++k) wake_next_[wake_list_[k]] = 0;
    wake_count_ = 0;
    return;
  }
  const double slow2 = solver_.sleep_speed_m_s * solver_.sleep_speed_m_s;
  const double sleep_d = solver_.sleep_distance_m;
  // Waking first, on the states at the start of the step: particles near a moving collider
  // (marked with this step's stamp, which the awake ones' calm count reads below) and those
  // queued (an awake neighbour moved, a bond broke). New awake particles are kept in lg_
  // (free until build_pairs) and appended to the awake list at the end.
  ++stamp_value_;
  const std::int32_t near_mark = stamp_value_;
  std::size_t woken = 0;
  auto wake = [&](std::int32_t i) {
    if (fixed_[i] || awake_[i]) return;
    awake_[i] = 1;
    calm_[i] = 0;
    lg_[woken++] = i;
  };
  for (const Collider& c : moving) {
    auto test = [&](std::int32_t j) {
      if (stamp_[j] == near_mark || fixed_[j]) return;
      if (!(signed_distance(c, x_[j], nullptr) < sleep_d)) return;
      stamp_[j] = near_mark;
      wake(j);
    };
    Vec3 lo, hi;
    if (collider_bounds(c, &lo, &hi)) {
      // The grid holds old positions: the query box is widened by how far they can be off
      // (Up to a skin old: see update_grid.)
      const Vec3 pad = Vec3::Constant(sleep_d + skin_);
      grid_.for_each_in_box(lo - pad, hi + pad, [&](std::int32_t j, const Vec3&) { test(j); });
    } else {
      for (std::size_t j = 0; j < n; ++j) test(static_cast<std::int32_t>(j));
    }
  }
  const std::size_t was_awake = active_count_;
  for (std::size_t k = 0; k < wake_count_; ++k) {
    const std::int32_t i = wake_list_[k];
    wake_next_[i] = 0;
    wake(i);
  }
  wake_count_ = 0;
  // Particles awake at the start of the step: calm steps, and sleep after enough of them.
  std::size_t survivors = 0;
  for (std::size_t k = 0; k < was_awake; ++k) {
    const std::int32_t i = active_[k];
    const bool calm = stamp_[i] != near_mark && v_[i].squaredNorm() < slow2;
    calm_[i] = calm ? static_cast<std::uint16_t>(std::min(calm_[i] + 1, 60000)) : 0;
    if (calm_[i] >= kCalmStepsToSleep) {
      awake_[i] = 0;
      v_[i] = Vec3::Zero();
      // Its displacement since the grid build stays in the rebuild test (update_grid).
      const double d2 = min_image(x_[i] - x_built_[i]).squaredNorm();
      if (d2 > frozen_disp2_[1]) {
        frozen_disp2_[1] = d2;
        if (frozen_disp2_[1] > frozen_disp2_[0]) std::swap(frozen_disp2_[0], frozen_disp2_[1]);
      }
    } else {
      active_[survivors++] = i;
    }
  }
  // The awake list stays sorted by particle index (build_pairs relies on it): the woken ones,
  // sorted, are merged in from the back.
  std::sort(lg_.begin(), lg_.begin() + static_cast<std::ptrdiff_t>(woken));
  std::size_t a = survivors, b = woken, out = survivors + woken;
  while (b > 0) {
    if (a > 0 && active_[a - 1] > lg_[b - 1]) active_[--out] = active_[--a];
    else active_[--out] = lg_[--b];
  }
  active_count_ = survivors + woken;
}

// This step's particles in local numbering and their pairs. The awake particles' rows give
// the pairs with an awake particle and, as their sleeping neighbours within R, the halo; the
// halo's rows give the remaining pairs (the halo's densities must be complete) and the outer
// particles. Pairs split by reach: near ones (density radius) from the front of the arrays,
// far ones from the back.
void Nucleus::build_pairs() {
  const double R2 = radius_ * radius_;
  const double Rd2 = density_radius_ * density_radius_;
  const std::size_t cap = pair_cap_;
  near_ = far_ = 0;
  na_ = active_count_;
  for (std::size_t k = 0; k < na_; ++k) {
    const std::int32_t i = active_[k];
    lg_[k] = i;
    local_[i] = static_cast<std::int32_t>(k);
    x_start_[i] = x_[i];
  }
  nh_ = na_;
  auto emit = [&](std::int32_t li, std::int32_t lj, const Vec3& d, double r2, std::int32_t bond) {
    if (near_ + far_ >= cap) {
      pairs_overflow_ = true;
      return;
    }
    const std::size_t p = r2 < Rd2 ? near_++ : cap - 1 - far_++;
    const double r = std::sqrt(r2);
    pair_i_[p] = li;
    pair_j_[p] = lj;
    pair_r_[p] = r;
    pair_n_[p] = d * (1.0 / r);
    if (bond >= 0 && !bond_alive_[bond]) bond = -1;
    pair_bond_[p] = bond;
    if (bond >= 0 && loose_possible_) bond_in_pair_[bond] = 1;
  };
  // The pairs of local particle k from its row. A neighbour numbered below k was paired from
  // its own side (awake ones before halo ones, halo ones by index; self never appears); one
  // not numbered yet joins the step with the next local number from `next` (the halo for
  // awake particles, the outer ring for halo ones).
  // Starts local particle k's pairs: its Verlet row (built if needed) and where its near and
  // far pairs begin.
  auto open_row = [&](std::size_t k) {
    const std::int32_t i = lg_[k];
    ensure_row(i);
    row_near_[k] = static_cast<std::int32_t>(near_);
    row_far_[k] = static_cast<std::int32_t>(far_);
    return i;
  };
  auto pair_row = [&](std::size_t k, std::size_t& next) {
    const std::int32_t i = open_row(k);
    const std::int32_t* rj = row_j_.data() + row_start_[i];
    const std::int32_t* rb = row_bond_.data() + row_start_[i];
    const Vec3 xi = x_[i];
    for (std::int32_t c = 0; c < row_len_[i]; ++c) {
      const std::int32_t j = rj[c];
      std::int32_t lj = local_[j];
      if (lj >= 0 && lj < static_cast<std::int32_t>(k)) continue;
      const Vec3 d = min_image(x_[j] - xi);
      const double r2 = d.squaredNorm();
      if (r2 >= R2 || r2 <= 0.0) continue;
      if (lj < 0) {
        lj = static_cast<std::int32_t>(next++);
        local_[j] = lj;
        lg_[lj] = j;
      }
      emit(static_cast<std::int32_t>(k), lj, d, r2, rb[c]);
    }
  };
  // Awake rows. The awake list is sorted by particle index, so an awake neighbour numbered
  // below k is exactly an awake neighbour of lower index: the row's upper part (higher
  // indices) is paired whole, its lower part only with particles that are not awake. Rows are
  // ordered by distance within each part, so the range and near/far tests branch alike from
  // row to row.
  const bool propagate_wake = solver_.sleep_enabled;
  const double slow2 = solver_.sleep_speed_m_s * solver_.sleep_speed_m_s;
  // An entry of the upper part's beyond bucket that was at least R + disp_bound_ away at the
  // build is at least R away now (no particle has moved farther; a 1e-6 relative margin
  // covers the single-precision distances): the range test below would reject it, so it is
  // skipped on its build distance alone. (Periodic domains: not used.)
  // Lower parts pair only the particles that are not awake. When there are few of those, the
  // rows that can hold one are marked from its side, and the others skip their lower part: a
  // non-awake j is in the lower part of row i only if i > j lies in the 27 grid cells around
  // j's build position (the cells are neighbours of each other both ways).
  const std::size_t n_all = x_.size();
  const bool mark_lower = (n_all - na_) * 16 <= na_;
  std::int32_t lower_mark = 0;
  if (mark_lower) {
    lower_mark = ++stamp_value_;
    std::size_t a = 0;
    for (std::size_t j = 0; j < n_all; ++j) {
      const std::int32_t jj = static_cast<std::int32_t>(j);
      if (a < na_ && active_[a] == jj) {
        ++a;
        continue;
      }
      grid_.for_each_near(x_built_[j], [&](std::int32_t i, const Vec3&) {
        if (i > jj) stamp_[i] = lower_mark;
      });
    }
  }
  const double reach_now = (radius_ + disp_bound_) * (1.0 + 1e-6);
  const float far2 = periodic_ ? std::numeric_limits<float>::infinity()
                               : static_cast<float>(reach_now * reach_now * (1.0 + 1e-6));
  for (std::size_t k = 0; k < na_; ++k) {
    const std::int32_t i = open_row(k);
    const std::int32_t* rj = row_j_.data() + row_start_[i];
    const std::int32_t* rb = row_bond_.data() + row_start_[i];
    const std::int32_t upper = row_upper_[i];
    const Vec3 xi = x_[i];
    // Wake propagation for the next step: a frozen neighbour of a moving particle wakes.
    const bool moving_i = propagate_wake && v_[i].squaredNorm() >= slow2;
    auto visit = [&](std::int32_t c) {
      const std::int32_t j = rj[c];
      const Vec3 d = min_image(x_[j] - xi);
      const double r2 = d.squaredNorm();
      if (r2 >= R2 || r2 <= 0.0) return;
      std::int32_t lj = local_[j];
      if (lj < 0) {
        lj = static_cast<std::int32_t>(nh_++);
        local_[j] = lj;
        lg_[lj] = j;
      }
      if (moving_i && lj >= static_cast<std::int32_t>(na_) && !fixed_[j] && !wake_next_[j]) {
        wake_next_[j] = 1;
        wake_list_[wake_count_++] = j;
      }
      emit(static_cast<std::int32_t>(k), lj, d, r2, rb[c]);
    };
    const float* rr = row_r2_.data() + row_start_[i];
    const std::int32_t beyond = row_beyond_[i];
    for (std::int32_t c = 0; c < beyond; ++c) visit(c);
    for (std::int32_t c = beyond; c < upper; ++c)
      if (rr[c] < far2) visit(c);
    if (!mark_lower || stamp_[i] == lower_mark)
      for (std::int32_t c = upper; c < row_len_[i]; ++c)
        if (!awake_[rj[c]]) visit(c);
  }
  near_awake_ = near_;
  far_awake_ = far_;
  nl_ = nh_;
  for (std::size_t k = na_; k < nh_; ++k) pair_row(k, nl_);
  row_near_[nh_] = static_cast<std::int32_t>(near_);
  row_far_[nh_] = static_cast<std::int32_t>(far_);
  pairs_ = near_ + far_;
  // Bonds stretched beyond the interaction radius (possible only when delta_max > R - L) are
  // applied on their own; the other end joins the step if it is not in it yet.
  // A live bond is at most L + delta_max long at the start of a step (longer ones broke at the
  // end of the last one), so when every bond's L + delta_max is inside R there are none.
  loose_bonds_ = 0;
  for (std::size_t k = 0; k < (loose_possible_ ? na_ : 0); ++k) {
    const std::int32_t i = lg_[k];
    for (std::int32_t a = bond_adj_start_[i]; a < bond_adj_start_[i + 1]; ++a) {
      const std::int32_t b = bond_adj_[a];
      if (!bond_alive_[b] || bond_in_pair_[b]) continue;
      const std::int32_t j = bond_ij_[2 * b] == i ? bond_ij_[2 * b + 1] : bond_ij_[2 * b];
      std::int32_t lj = local_[j];
      if (lj >= 0 && lj < static_cast<std::int32_t>(k)) continue;  // awake, counted from j
      if (lj < 0) {
        lj = static_cast<std::int32_t>(nl_++);
        local_[j] = lj;
        lg_[lj] = j;
      }
      // Oriented as the bond is (i -> j in bond order), like a pair.
      const bool forward = bond_ij_[2 * b] == i;
      loose_[loose_bonds_] = b;
      loose_ij_[2 * loose_bonds_] = forward ? static_cast<std::int32_t>(k) : lj;
      loose_ij_[2 * loose_bonds_ + 1] = forward ? lj : static_cast<std::int32_t>(k);
      ++loose_bonds_;
    }
  }
  if (loose_possible_) {
    for (std::size_t p = 0; p < near_; ++p)
      if (pair_bond_[p] >= 0) bond_in_pair_[pair_bond_[p]] = 0;
    for (std::size_t p = cap - far_; p < cap; ++p)
      if (pair_bond_[p] >= 0) bond_in_pair_[pair_bond_[p]] = 0;
  }
  frozen_moving_ = false;
  for (std::size_t k = na_; k < nl_; ++k) frozen_moving_ = frozen_moving_ || fixed_[lg_[k]];
}

// Walls: for each particle of the step near a collider, the no-slip coupling, the density and
// second moment of the lattice sites inside the solid, and the contact constraint. A collider
// whose bounding box is farther than any of these reach is skipped (its surface is at least
// that far), unless culling is switched off.
void Nucleus::setup_walls(double dt, std::span<const Collider> moving) {
  wall_count_ = 0;
  wall_particles_ = 0;
  con_particles_ = 0;
  // A lattice site within R of the particle can be inside the solid only if d < R + h/2.
  const double wall_range = radius_ + 0.5 * h_;
  const std::size_t n_static = statics_.size();
  const std::size_t n_coll = n_static + moving.size();
  // Bounding boxes and speed bounds of the colliders.
  std::array<Vec3, 32> lo, hi;
  std::array<bool, 32> bounded;
  for (std::size_t c = 0; c < n_coll; ++c) {
    const Collider& col = c < n_static ? statics_[c] : moving[c - n_static];
    bounded[c] = solver_.contact_culling && collider_bounds(col, &lo[c], &hi[c]);
  }
  for (std::size_t k = 0; k < nh_; ++k) {
    density_[k] = 0.0;
    second_moment_[k] = 0.0;
    wall_slot_[k] = -1;
  }
  for (std::size_t k = 0; k < na_; ++k) {
    con_slot_[k] = -1;
    near_colliders_[k] = 0;
    all_colliders_[k] = solver_.contact_culling ? 0 : 1;
  }
  // Static colliders per particle. A static collider whose lower distance bound (box gap, or
  // the exact distance of a half-space) was at least wall_range + margin where the mask was
  // found is at least wall_range away while the particle stays within the margin of that
  // place (distances are 1-Lipschitz); when also the contact reach bound is inside the wall
  // range (|v| dt <= wall_range - contact - 0.1 h), the test below would skip it, so it is
  // left out without evaluating anything (bit-identical).
  const double mask_margin = kStaticMaskMargin * h_;
  const double mask_margin2 = mask_margin * mask_margin;
  const double mask_far = wall_range * (1.0 + 1e-9) + 1e-6 * h_ + mask_margin;
  const double slow_reach = wall_range - contact_ - 0.1 * h_;
  const double slow_v2 = slow_reach > 0.0 ? (slow_reach / dt) * (slow_reach / dt) : -1.0;
  const std::uint32_t all_statics =
      n_static >= 32 ? ~0u : ((1u << n_static) - 1u);
  const std::uint32_t moving_bits = (n_coll >= 32 ? ~0u : ((1u << n_coll) - 1u)) & ~all_statics;
  for (std::size_t k = 0; k < nh_; ++k) {
    const std::int32_t i = lg_[k];
    const bool awake = k < na_;
    const Vec3 xi = x_[i];
    const Vec3 vi = v_[i];
    const double vi_norm = vi.norm();
    std::uint32_t statics_mask = all_statics;
    if (solver_.contact_culling && vi.squaredNorm() <= slow_v2 * (1.0 - 1e-9)) {
      if (!((xi - static_ref_[i]).squaredNorm() <= mask_margin2)) {
        std::uint32_t mask = 0;
        for (std::size_t kc = 0; kc < n_static; ++kc) {
          const Collider& c = statics_[kc];
          double gap = 0.0;  // lower bound of the distance to the solid
          if (bounded[kc]) gap = box_gap(xi, lo[kc], hi[kc]);
          else if (c.kind == ColliderKind::kHalfSpace)
            gap = signed_distance_local(c, to_local(c.pose, frame_identity_[kc] != 0, xi), nullptr);
          if (!(gap >= mask_far)) mask |= 1u << kc;
        }
        static_mask_[i] = mask;
        static_ref_[i] = xi;
      }
      statics_mask = static_mask_[i];
    }
    int hits = 0;
    Vec3 grad_sum = Vec3::Zero();
    // Contact normals and target normal velocities of this particle (up to 3).
    Vec3 cn[3];
    double ct[3];
    int nc = 0;
    // The colliders to look at (the statics in the mask, every moving one), in index order.
    for (std::uint32_t todo = statics_mask | moving_bits; todo != 0; todo &= todo - 1) {
      const std::size_t kc = static_cast<std::size_t>(__builtin_ctz(todo));
      const Collider& c = kc < n_static ? statics_[kc] : moving[kc - n_static];
      if (bounded[kc]) {
        // The surface is at least box_gap away; the contact reach is at most
        // contact + 0.1 h + |v_i - v_wall| dt. (Compared squared: the bound has a 1e-9 margin,
        // and a collider kept by rounding is skipped by the exact test below.)
        const double v_wall =
            kc < n_static ? 0.0
                          : frame_lin_speed_[kc] +
                                (frame_ang_speed_[kc] != 0.0
                                     ? frame_ang_speed_[kc] * (xi - c.pose.position).norm()
                                     : 0.0);
        const double reach_bound = contact_ + 0.1 * h_ + (vi_norm + v_wall) * dt;
        const double bound = std::max(wall_range, reach_bound) * (1.0 + 1e-9);
        if (box_gap2(xi, lo[kc], hi[kc]) >= bound * bound) continue;
      }
      Vec3 normal;
      const bool unrotated = frame_identity_[kc] != 0;
      const double d = signed_distance_local(c, to_local(c.pose, unrotated, xi), &normal);
      if (!unrotated) normal = c.pose.orientation * normal;
      const Vec3 vw = kc < n_static ? Vec3::Zero() : c.velocity_at(xi);
      const double vn_rel = (vi - vw).dot(normal);
      const double reach = contact_ + 0.1 * h_ + std::max(0.0, -vn_rel) * dt;
      if (d >= wall_range && d >= reach) continue;
      if (hits >= kMaxWallHitsPerParticle || wall_count_ >= walls_.size()) {
        if (awake) all_colliders_[k] = 1;  // not tracked: the projection checks everything
        continue;
      }
      ++hits;
      if (awake) near_colliders_[k] |= 1u << kc;
      WallHit& w = walls_[wall_count_++];
      w.particle = static_cast<std::int32_t>(k);
      w.collider = kc < n_static ? -1 - static_cast<std::int32_t>(kc)
                                 : static_cast<std::int32_t>(kc - n_static);
      w.normal = normal;
      w.v_wall = vw;
      w.point = xi - d * normal;
      w.distance = d;
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
      int face_axis = -1;
      if (d < wall_range && flat_face(c, xi, d, normal, &face_axis)) {
        // An axis-aligned flat face seen by every site: the sums depend on d only (table).
        const WallTableEntry e = wall_table_at(d);
        density_[k] += e.n;
        second_moment_[k] += e.s2;
        w.grad = e.grad * normal;
        w.visc = e.visc_t * Eigen::Matrix3d::Identity();
        w.visc(face_axis, face_axis) = e.visc_n;
      } else if (d < wall_range) {
        // The sums depend on where the particle is relative to the solid only (cached; read
        // in place, not copied).
        SiteSums uncached;
        const SiteSums& sums =
            solver_.wall_sum_cache
                ? cached_site_sums(static_cast<std::int32_t>(kc), c, i, xi, d)
                : (uncached = site_sums(c, static_cast<std::int32_t>(kc), xi,
                                        to_local(c.pose, unrotated, xi), d));
        density_[k] += sums.n;
        second_moment_[k] += sums.s2;
        w.grad = sums.grad;
        w.visc = sums.visc;
      } else {
        w.grad = Vec3::Zero();  // beyond the wall range: only a contact
        w.visc = Eigen::Matrix3d::Zero();
      }
      grad_sum += w.grad;
      // Contact constraint: approaching or resting particles within reach. The normal velocity
      // is set to what brings the particle exactly to the contact distance, or to its current
      // normal velocity if that is slower (no pull toward the wall). Penetrating particles are
      // stopped in the normal direction and pushed out by position after the solve.
      w.contact = false;
      if (awake && d < reach && vn_rel <= 1e-12 && (d < contact_ || !release_[i]) && nc < 3) {
        const double approach = d > contact_ ? -(d - contact_) / dt : 0.0;
        cn[nc] = normal;
        ct[nc] = vw.dot(normal) + std::max(approach, std::min(vn_rel, 0.0));
        ++nc;
        w.contact = true;
      }
    }
    if (hits > 0) {
      const std::size_t slot = wall_particles_++;
      wall_slot_[k] = static_cast<std::int32_t>(slot);
      wall_particle_[slot] = static_cast<std::int32_t>(k);
      wall_g_[slot] = grad_sum;
      wall_c_[slot] = Eigen::Matrix3d::Zero();
    }
    if (!awake) continue;
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
      const std::size_t slot = con_particles_++;
      con_slot_[k] = static_cast<std::int32_t>(slot);
      con_particle_[slot] = static_cast<std::int32_t>(k);
      con_count_[slot] = static_cast<std::uint8_t>(ne);
      for (int a = 0; a < ne; ++a) con_e_[slot][a] = e[a];
      con_v_[slot] = vc;
    }
  }
}

// Wall sums of collider `kc`'s lattice sites around a particle at x (local: x in the
// collider's frame), d from its surface: each site within R counts with its occupancy (see
// setup_walls). The sites are placed in the collider's frame with the offsets rotated once per
// step (collider_frames), and a box's sites farther than h/2 outside its faces along any local
// axis are rejected before the distance (their occupancy is 0): a particle beside the moving
// blade recomputes these sums nearly every step, and most of its sites are outside the blade.
Nucleus::SiteSums Nucleus::site_sums(const Collider& c, std::int32_t kc, const Vec3& x,
                                     const Vec3& local, double d) const {
  SiteSums sums;
  const double inv_d_eff = 1.0 / std::max(d, 0.25 * h_);
  const double inv_n0 = 1.0 / n0_;
  const double half = 0.5 * h_;
  const bool identity = frame_identity_[kc] != 0;
  const Vec3* offsets = identity ? site_offset_.data() : &site_local_[kc * site_offset_.size()];
  const bool box = c.kind == ColliderKind::kBox;
  const Vec3 reject = c.half_extents_m + Vec3::Constant(half);
  Vec3 grad_local = Vec3::Zero();
  for (std::size_t o = 0; o < site_offset_.size(); ++o) {
    // sd(site) >= d - |offset|: a site that far cannot be occupied.
    if (d - site_len_[o] >= half) continue;
    // An unrotated collider: the site's local point exactly as signed_distance() forms it.
    const Vec3 p = identity ? Vec3((x + site_offset_[o]) - c.pose.position)
                            : Vec3(local + offsets[o]);
    if (box && (p.x() >= reject.x() || -p.x() >= reject.x() || p.y() >= reject.y() ||
                -p.y() >= reject.y() || p.z() >= reject.z() || -p.z() >= reject.z()))
      continue;  // sd >= |p_a| - b_a >= h/2 on that axis
    Vec3 nq;
    const double sd = signed_distance_local(c, p, &nq);
    double slope = 0.0;
    const double occ = occupancy(sd, h_, &slope);
    if (occ <= 0.0) continue;
    sums.n += occ * site_w_[o];
    sums.s2 += occ * site_wv_[o] * site_r2_[o];
    grad_local += (slope * site_w_[o] * inv_n0) * nq;
    sums.visc += (occ * site_wv_[o] * (1.0 + std::max(0.0, -sd) * inv_d_eff)) * site_uu_[o];
  }
  sums.grad = identity ? grad_local : Vec3(c.pose.orientation * grad_local);
  return sums;
}

// Per collider of this step (statics, then moving): its linear and angular speed, whether its
// orientation is the identity, and otherwise the lattice site offsets in its frame.
void Nucleus::collider_frames(std::span<const Collider> moving) {
  const std::size_t n_static = statics_.size();
  const std::size_t sites = site_offset_.size();
  for (std::size_t kc = 0; kc < n_static + moving.size(); ++kc) {
    const Collider& c = kc < n_static ? statics_[kc] : moving[kc - n_static];
    frame_lin_speed_[kc] = c.linear_velocity_m_s.norm();
    frame_ang_speed_[kc] = c.angular_velocity_rad_s.norm();
    const Quat& q = c.pose.orientation;
    const bool identity = q.w() == 1.0 && q.x() == 0.0 && q.y() == 0.0 && q.z() == 0.0;
    frame_identity_[kc] = identity ? 1 : 0;
    if (identity) continue;
    const Eigen::Matrix3d to_local = q.conjugate().toRotationMatrix();
    for (std::size_t o = 0; o < sites; ++o) site_local_[kc * sites + o] = to_local * site_offset_[o];
  }
}

// site_sums of collider `kc` (index over statics then moving) for particle i at x, from the
// cache while i's position in the collider's frame has moved less than the tolerance and the
// collider has turned less than the tolerance over R since they were computed: the sums are
// a function of that relative placement only (a translated collider carries its sums along;
// the lattice of sites is world-aligned, hence the turn limit).
const Nucleus::SiteSums& Nucleus::cached_site_sums(std::int32_t kc, const Collider& c,
                                                   std::int32_t i, const Vec3& x, double d) {
  const double tol = solver_.wall_sum_cache_tolerance * h_;
  const Vec3 local = to_local(c.pose, frame_identity_[kc] != 0, x);
  SiteSums* entries = &site_cache_[kMaxWallHitsPerParticle * static_cast<std::size_t>(i)];
  SiteSums* slot = nullptr;
  for (int e = 0; e < kMaxWallHitsPerParticle; ++e) {
    if (entries[e].collider == kc) slot = &entries[e];
  }
  if (slot) {
    const bool placed = (local - slot->local).squaredNorm() < tol * tol;
    const bool turned = !(std::abs(c.pose.orientation.dot(slot->orientation)) > cache_turn_cos_);
    if (placed && !turned) return *slot;
  } else {
    slot = &entries[site_cache_next_[i]];  // round robin over the particle's entries
    site_cache_next_[i] = static_cast<std::uint8_t>((site_cache_next_[i] + 1) % kMaxWallHitsPerParticle);
  }
  *slot = site_sums(c, kc, x, local, d);
  slot->collider = kc;
  slot->local = local;
  slot->orientation = c.pose.orientation;
  return *slot;
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

namespace {

/// Symmetric 3x3 block stored as xx, yy, zz, xy, xz, yz.
using Sym3 = std::array<double, 6>;

inline void add_outer(Sym3& m, double a, const Vec3& n) {
  m[0] += a * n.x() * n.x();
  m[1] += a * n.y() * n.y();
  m[2] += a * n.z() * n.z();
  m[3] += a * n.x() * n.y();
  m[4] += a * n.x() * n.z();
  m[5] += a * n.y() * n.z();
}

/// Inverse of a symmetric positive definite 3x3 block (adjugate over determinant).
inline Sym3 inverse(const Sym3& m) {
  const double xx = m[0], yy = m[1], zz = m[2], xy = m[3], xz = m[4], yz = m[5];
  const double c00 = yy * zz - yz * yz;
  const double c01 = xz * yz - xy * zz;
  const double c02 = xy * yz - xz * yy;
  const double det = xx * c00 + xy * c01 + xz * c02;
  const double inv = 1.0 / det;
  return {c00 * inv,
          (xx * zz - xz * xz) * inv,
          (xx * yy - xy * xy) * inv,
          c01 * inv,
          c02 * inv,
          (xy * xz - xx * yz) * inv};
}

inline Vec3 mul(const Sym3& m, const Vec3& v) {
  return Vec3(m[0] * v.x() + m[3] * v.y() + m[4] * v.z(),
              m[3] * v.x() + m[1] * v.y() + m[5] * v.z(),
              m[4] * v.x() + m[5] * v.y() + m[2] * v.z());
}

}  // namespace

// Per-step coefficients, right-hand side and block-Jacobi preconditioner. Rows of the system
// are needed for the awake particles only; pairs without an awake particle enter only the
// densities and second moments (of the halo). Three passes over the pairs: neighbour sums;
// then, per pair with an awake particle, its coefficient, its forces on the right-hand side,
// its share of the diagonal blocks and the solver's compact record.
void Nucleus::assemble(double dt) {
  const double R = radius_;
  const double Rd = density_radius_;
  const std::size_t cap = pair_cap_;
  const std::size_t far_begin = cap - far_;
  const std::size_t far_awake_begin = cap - far_awake_;
  for (std::size_t k = nh_; k < nl_; ++k) {
    density_[k] = 0.0;  // outer particles: partial sums, never read
    second_moment_[k] = 0.0;
  }
  // Neighbour sums: density (kernel units) and second moment, the kernels' q from the
  // reciprocal radii (every near pair is inside both radii).
  const double inv_R = 1.0 / R, inv_Rd = 1.0 / Rd;
  const double slope_scale = -3.0 * inv_Rd / n0_;  // dw/dr / n0 = slope_scale q^2
  // Row by row (every pair of row k has k as its first end), the first end's sums in
  // registers.
  const std::int32_t* pj = pair_j_.data();
  const double* pr = pair_r_.data();
  for (std::size_t k = 0; k < nh_; ++k) {
    double dk = 1.0;  // self
    double mk = 0.0;
    for (std::int32_t p = row_near_[k]; p < row_near_[k + 1]; ++p) {
      const std::int32_t j = pj[p];
      const double r = pr[p];
      const double qd = std::max(0.0, 1.0 - r * inv_Rd);
      const double w = kernel_of(qd);
      const double wv = viscous_weight_of(std::max(0.0, 1.0 - r * inv_R));
      const double m2 = wv * r * r;
      dk += w;
      density_[j] += w;
      pair_g_[p] = slope_scale * qd * qd;
      mk += m2;
      second_moment_[j] += m2;
      pair_a_[p] = wv;
    }
    for (std::size_t p = cap - row_far_[k + 1]; p < cap - row_far_[k]; ++p) {
      const std::int32_t j = pj[p];
      const double r = pr[p];
      const double wv = viscous_weight_of(std::max(0.0, 1.0 - r * inv_R));
      const double m2 = wv * r * r;
      mk += m2;
      second_moment_[j] += m2;
      pair_a_[p] = wv;
    }
    density_[k] += dk;
    second_moment_[k] += mk;
  }

  // Per particle. Viscous coefficients c_ij = w_ij 2 mu V / T, with T the weighted fourth
  // moment sum w r_x^2 r_z^2 / r^2 of the neighbourhood: the stress of the pair operator under
  // a shear rate gamma is gamma T c / (2 V w), so this gives tau = mu gamma (see the file
  // comment). T is the rest lattice's t0 scaled by the particle's own weighted second moment
  // S / s0 (for isotropic directions T = S / 15), so a disordered or compressed neighbourhood
  // is normalised by what it actually holds. S is floored at 0.6 s0 so a sparse neighbourhood
  // (free surface, loose particles) does not get an unbounded coefficient.
  // Pressure constraint C_i and which particles carry it (compression only, with a 1 % margin
  // so a particle about to be compressed is already implicit).
  for (std::size_t k = 0; k < nh_; ++k) {
    const std::int32_t i = lg_[k];
    visc_coef_[k] =
        2.0 * mu_[i] * volume_ * s0_ / (t0_ * std::max(second_moment_[k], 0.6 * s0_));
    constraint_[k] = density_[k] / n0_ - 1.0;
    press_coef_[k] = constraint_[k] > -0.01 ? dt * dt * kappa_[i] * volume_ : 0.0;
  }
  for (std::size_t k = nh_; k < nl_; ++k) {
    constraint_[k] = 0.0;
    press_coef_[k] = 0.0;
    visc_coef_[k] = 0.0;
  }
  // Right-hand side: forces at the start of the step (as dt * f) and M v0; rows beyond the
  // awake particles are scratch. Walls: the no-slip tensor, the wall pressure, the no-slip
  // drag toward a moving wall, and the density change the wall's own motion causes
  // (s_i = press_coef * sum_w grad . v_w, scattered through grad C below).
  for (std::size_t k = 0; k < nl_; ++k) {
    const std::int32_t i = lg_[k];
    rhs_[k] = dt * (mass_[i] * gravity_ + f_ext_[i]);
  }
  for (std::size_t k = 0; k < na_; ++k) {
    mass_l_[k] = mass_[lg_[k]];
    rhs_[k] += mass_l_[k] * v_[lg_[k]];
  }
  for (std::size_t k = 0; k < nh_; ++k) s_[k] = 0.0;
  for (std::size_t w = 0; w < wall_count_; ++w) {
    const WallHit& hit = walls_[w];
    const std::int32_t k = hit.particle;
    wall_c_[wall_slot_[k]] += (dt * visc_coef_[k]) * hit.visc;
    rhs_[k] += (dt * visc_coef_[k]) * (hit.visc * hit.v_wall);
    s_[k] += hit.grad.dot(hit.v_wall);
  }
  for (std::size_t k = 0; k < nh_; ++k) s_[k] *= press_coef_[k];
  for (std::size_t w = 0; w < wall_particles_; ++w) {
    const std::int32_t k = wall_particle_[w];
    rhs_[k] -= dt * kappa_[lg_[k]] * volume_ * std::max(constraint_[k], 0.0) * wall_g_[w];
    rhs_[k] += s_[k] * wall_g_[w];
  }
  // Block-Jacobi preconditioner: the 3x3 diagonal blocks of the system matrix (awake rows).
  // grad_i C_i = -sum_j g_ij n_ij + wall_g_i, accumulated in q_ as scratch.
  for (std::size_t k = 0; k < nh_; ++k) {
    const double m = k < na_ ? mass_l_[k] : 1.0;
    diag_inv_[k] = {m, m, m, 0.0, 0.0, 0.0};
    q_[k] = Vec3::Zero();
  }
  for (std::size_t w = 0; w < wall_particles_; ++w) {
    const std::int32_t k = wall_particle_[w];
    const Eigen::Matrix3d& C = wall_c_[w];
    Sym3& d = diag_inv_[k];
    d[0] += C(0, 0);
    d[1] += C(1, 1);
    d[2] += C(2, 2);
    d[3] += 0.5 * (C(0, 1) + C(1, 0));
    d[4] += 0.5 * (C(0, 2) + C(2, 0));
    d[5] += 0.5 * (C(1, 2) + C(2, 1));
    q_[k] = wall_g_[w];
  }
  // Pairs with an awake particle: the implicit coefficient dt c_ij (+ dt^2 k of its bond),
  // the bond force k (r - L) along the pair, the pressure force, the wall-motion term, the
  // diagonal blocks, and the solver's record. The solver's copy is single precision: the
  // iterations stream it, so its size sets their speed; rounding perturbs the operator by
  // ~1e-7 relative (far below the solve tolerance) and symmetrically (both ends of a pair read
  // the same record), so it stays symmetric positive definite.
  // Per particle of the step: the pressure force factor dt kappa V max(C, 0) and half the
  // viscous coefficient times dt (zero beyond the halo).
  double* pf = s_pf_.data();
  double* hv = s_hv_.data();
  for (std::size_t k = 0; k < nl_; ++k) {
    pf[k] = dt * kappa_[lg_[k]] * volume_ * std::max(constraint_[k], 0.0);
    hv[k] = 0.5 * dt * visc_coef_[k];
  }
  const double* pc = press_coef_.data();
  const double dt2 = dt * dt;
  // Row by row over the awake particles (their rows hold exactly the pairs with an awake
  // particle), the first end's sums in registers.
  for (std::size_t k = 0; k < nh_; ++k) pf[k] -= s_[k];  // pressure force less wall motion
  // The arrays as local pointers: the scattered stores below could alias the vectors' own
  // members, so the compiler would otherwise reload every base pointer for every pair.
  const Vec3* pn = pair_n_.data();
  const double* pa = pair_a_.data();
  const double* pg = pair_g_.data();
  const std::int32_t* pb = pair_bond_.data();
  const double* bk = bond_k_.data();
  const double* brest = bond_rest_.data();
  Vec3* rhs = rhs_.data();
  Vec3* qv = q_.data();
  Sym3* diag = diag_inv_.data();
  PairKernel* kern = kernel_.data();
  const std::int32_t* rnear = row_near_.data();
  const std::int32_t* rfar = row_far_.data();
  for (std::size_t i = 0; i < na_; ++i) {
    const double hv_i = hv[i], pf_i = pf[i], pc_i = pc[i];
    Vec3 rhs_i = Vec3::Zero();
    Vec3 q_i = Vec3::Zero();
    double d0 = 0.0, d1 = 0.0, d2 = 0.0, d3 = 0.0, d4 = 0.0, d5 = 0.0;
    for (std::int32_t p = rnear[i]; p < rnear[i + 1]; ++p) {
      const std::int32_t j = pj[p];
      const Vec3& nn = pn[p];
      double a = pa[p] * (hv_i + hv[j]);
      const double g = pg[p];
      double fs = (pf_i + pf[j]) * g;
      const std::int32_t b = pb[p];
      if (b >= 0) {
        const double k = bk[b];
        a += dt2 * k;
        fs += dt * k * (pr[p] - brest[b]);
      }
      const Vec3 f = fs * nn;
      rhs_i += f;
      rhs[j] -= f;
      const double g2 = g * g;
      const double ai = a + pc[j] * g2, aj = a + pc_i * g2;
      const double xx = nn.x() * nn.x(), yy = nn.y() * nn.y(), zz = nn.z() * nn.z();
      const double xy = nn.x() * nn.y(), xz = nn.x() * nn.z(), yz = nn.y() * nn.z();
      d0 += ai * xx; d1 += ai * yy; d2 += ai * zz; d3 += ai * xy; d4 += ai * xz; d5 += ai * yz;
      Sym3& dj = diag[j];
      dj[0] += aj * xx; dj[1] += aj * yy; dj[2] += aj * zz;
      dj[3] += aj * xy; dj[4] += aj * xz; dj[5] += aj * yz;
      q_i -= g * nn;
      qv[j] += g * nn;
      kern[p] = {static_cast<float>(nn.x()), static_cast<float>(nn.y()),
                 static_cast<float>(nn.z()), static_cast<float>(g), j, static_cast<float>(a)};
    }
    for (std::size_t p = cap - rfar[i + 1]; p < cap - rfar[i]; ++p) {
      const std::int32_t j = pj[p];
      const Vec3& nn = pn[p];
      double a = pa[p] * (hv_i + hv[j]);
      const std::int32_t b = pb[p];
      if (b >= 0) {
        const double k = bk[b];
        a += dt2 * k;
        const Vec3 f = (dt * k * (pr[p] - brest[b])) * nn;
        rhs_i += f;
        rhs[j] -= f;
      }
      const double xx = nn.x() * nn.x(), yy = nn.y() * nn.y(), zz = nn.z() * nn.z();
      const double xy = nn.x() * nn.y(), xz = nn.x() * nn.z(), yz = nn.y() * nn.z();
      d0 += a * xx; d1 += a * yy; d2 += a * zz; d3 += a * xy; d4 += a * xz; d5 += a * yz;
      Sym3& dj = diag[j];
      dj[0] += a * xx; dj[1] += a * yy; dj[2] += a * zz;
      dj[3] += a * xy; dj[4] += a * xz; dj[5] += a * yz;
      kern[p] = {static_cast<float>(nn.x()), static_cast<float>(nn.y()),
                 static_cast<float>(nn.z()), 0.0f, j, static_cast<float>(a)};
    }
    rhs[i] += rhs_i;
    qv[i] += q_i;
    Sym3& di = diag[i];
    di[0] += d0; di[1] += d1; di[2] += d2; di[3] += d3; di[4] += d4; di[5] += d5;
  }
  // Pairs without an awake particle never act on an awake row (coefficient 0); their density
  // gradient still matters when a frozen particle moves (a full apply, the only reader).
  if (frozen_moving_) {
    for (std::size_t p = near_awake_; p < near_; ++p)
      kernel_[p] = {static_cast<float>(pair_n_[p].x()), static_cast<float>(pair_n_[p].y()),
                    static_cast<float>(pair_n_[p].z()), static_cast<float>(pair_g_[p]),
                    pair_j_[p], 0.0f};
    for (std::size_t p = far_begin; p < far_awake_begin; ++p)
      kernel_[p] = {0.0f, 0.0f, 0.0f, 0.0f, pair_j_[p], 0.0f};
  }
  // Loose bonds cache their direction and implicit coefficient dt^2 k for the solver.
  for (std::size_t k = 0; k < loose_bonds_; ++k) {
    const std::int32_t b = loose_[k];
    loose_a_[k] = 0.0;
    const std::int32_t li = loose_ij_[2 * k], lj = loose_ij_[2 * k + 1];
    const Vec3 d = min_image(x_[lg_[lj]] - x_[lg_[li]]);
    const double r = d.norm();
    if (r <= 0.0) continue;
    loose_n_[k] = d / r;
    loose_a_[k] = dt * dt * bond_k_[b];
    const Vec3 f = dt * bond_k_[b] * (r - bond_rest_[b]) * loose_n_[k];
    rhs_[li] += f;
    rhs_[lj] -= f;
    add_outer(diag_inv_[li], loose_a_[k], loose_n_[k]);
    add_outer(diag_inv_[lj], loose_a_[k], loose_n_[k]);
  }
  for (std::size_t k = 0; k < na_; ++k) {
    add_outer(diag_inv_[k], press_coef_[k], q_[k]);
    diag_inv_[k] = inverse(diag_inv_[k]);
  }
}

// y = A x for the system matrix A = M + dt C + dt^2 K (+ wall terms), on the awake rows.
// x must be zero on the frozen particles unless `full`; then every pair is applied (needed
// when a frozen particle is fixed and moves, so its velocity is not zero). Rows of y beyond
// the awake particles are scratch. Pairs are walked row by row (all pairs of local particle i
// have i as their first end and a larger second end), so the first end's sums stay in
// registers.
//
// The pair part runs in single precision on 4-lane vectors (x, y, z, 0): a pair's direction
// and gradient load as one vector, its relative velocity and force are one subtraction and
// one multiplication, which halves the instructions of the double 2 + 1 lane form. The
// operator's coefficients are single precision already (PairKernel); rounding x and the sums
// perturbs A x by ~1e-7 relative, far below the solve tolerance. Mass, walls and loose bonds
// stay double.
void Nucleus::apply(const Vec3* x, Vec3* y, bool full) {
  // A pair's first 16 bytes are loaded as one vector (direction, gradient).
  static_assert(offsetof(PairKernel, nx) == 0 && offsetof(PairKernel, g) == 3 * sizeof(float) &&
                    sizeof(PairKernel) >= sizeof(F4),
                "PairKernel must start with nx, ny, nz, g");
  const std::size_t rows = full ? nh_ : na_;   // rows whose pairs are applied
  const std::size_t span = full ? nl_ : nh_;   // particles those pairs reach
  const std::size_t cap = pair_cap_;
  F4* xf = apply_x_.data();
  F4* yf = apply_y_.data();
  float* s = apply_s_.data();
  const double* m = mass_l_.data();
  // Per particle, in one pass: the single-precision input, the mass and wall terms in y, and
  // the wall part of the divergence (wall_slot_ is set on [0, nh)).
  const std::int32_t* slot = wall_slot_.data();
  const std::size_t walled = std::min(span, nh_);
  auto init = [&](std::size_t k) {
    xf[k] = F4{static_cast<float>(x[k].x()), static_cast<float>(x[k].y()),
               static_cast<float>(x[k].z()), 0.0f};
    yf[k] = F4{0.0f, 0.0f, 0.0f, 0.0f};
    s[k] = 0.0f;
    if (k < walled && slot[k] >= 0) {
      const std::int32_t w = slot[k];
      y[k] += wall_c_[w] * x[k];
      s[k] = static_cast<float>(wall_g_[w].dot(x[k]));
    }
  };
  for (std::size_t k = 0; k < na_; ++k) {
    y[k] = m[k] * x[k];
    init(k);
  }
  for (std::size_t k = na_; k < span; ++k) {
    y[k] = Vec3::Zero();
    init(k);
  }
  // Loose bonds: dt^2 k n n^T on the relative velocity (pair bonds are in the pair term).
  for (std::size_t k = 0; k < loose_bonds_; ++k) {
    const std::int32_t i = loose_ij_[2 * k], j = loose_ij_[2 * k + 1];
    const Vec3& nn = loose_n_[k];
    const Vec3 f = loose_a_[k] * nn.dot(x[j] - x[i]) * nn;
    y[i] -= f;
    y[j] += f;
  }
  // n . d of a direction-and-gradient vector ng and a relative velocity d whose last lane is 0,
  // summed as (t0 + t2) + (t1 + t3); dot3x2 gives two of them with the same sums (so a row
  // gives the same bits whether its pairs go one or two at a time) in fewer shuffles.
  auto dot3 = [](const F4& ng, const F4& d) {
    F4 t = ng * d;
    t += __builtin_shufflevector(t, t, 2, 3, 0, 1);
    t += __builtin_shufflevector(t, t, 1, 0, 3, 2);
    return t[0];
  };
  auto dot3x2 = [](const F4& ng0, const F4& d0, const F4& ng1, const F4& d1, float& dn0,
                   float& dn1) {
    const F4 t0 = ng0 * d0, t1 = ng1 * d1;
    F4 u = __builtin_shufflevector(t0, t1, 0, 1, 4, 5) + __builtin_shufflevector(t0, t1, 2, 3, 6, 7);
    u += __builtin_shufflevector(u, u, 1, 0, 3, 2);
    dn0 = u[0];
    dn1 = u[2];
  };
  // Far pairs: viscosity and pair bonds (a n n^T on the relative velocity). Near pairs, first
  // pass: the divergence of the pressure (s), keeping each pair's relative normal velocity dn.
  const PairKernel* kr = kernel_.data();
  const std::int32_t* rn = row_near_.data();
  const std::int32_t* rf = row_far_.data();
  float* dnp = pair_dn_.data();
  // Pairs k and k+1 of a row: their kernels' first lanes (direction, and the gradient or 0)
  // and their relative normal velocities n . (x_j - x_i).
  auto two_pairs = [&](std::size_t k, const F4& xi, F4& n0, F4& n1, float& dn0, float& dn1) {
    std::memcpy(&n0, &kr[k], sizeof(F4));
    std::memcpy(&n1, &kr[k + 1], sizeof(F4));
    dot3x2(n0, xf[kr[k].j] - xi, n1, xf[kr[k + 1].j] - xi, dn0, dn1);
  };
  // Pairs k .. k+3: their kernels' first lanes and their relative normal velocities as one
  // vector, each summed as dot3 sums it, (t0 + t2) + (t1 + t3), in a 4 x 4 transpose-add.
  auto four_pairs = [&](std::size_t k, const F4& xi, F4& n0, F4& n1, F4& n2, F4& n3) {
    std::memcpy(&n0, &kr[k], sizeof(F4));
    std::memcpy(&n1, &kr[k + 1], sizeof(F4));
    std::memcpy(&n2, &kr[k + 2], sizeof(F4));
    std::memcpy(&n3, &kr[k + 3], sizeof(F4));
    const F4 t0 = n0 * (xf[kr[k].j] - xi), t1 = n1 * (xf[kr[k + 1].j] - xi);
    const F4 t2 = n2 * (xf[kr[k + 2].j] - xi), t3 = n3 * (xf[kr[k + 3].j] - xi);
    const F4 u01 = __builtin_shufflevector(t0, t1, 0, 1, 4, 5) +
                   __builtin_shufflevector(t0, t1, 2, 3, 6, 7);
    const F4 u23 = __builtin_shufflevector(t2, t3, 0, 1, 4, 5) +
                   __builtin_shufflevector(t2, t3, 2, 3, 6, 7);
    return F4(__builtin_shufflevector(u01, u23, 0, 2, 4, 6) +
              __builtin_shufflevector(u01, u23, 1, 3, 5, 7));
  };
  for (std::size_t i = 0; i < rows; ++i) {
    const F4 xi = xf[i];
    float si = 0.0f;
    std::int32_t p = rn[i];
    for (; p + 3 < rn[i + 1]; p += 4) {
      F4 ng0, ng1, ng2, ng3;
      const F4 dn = four_pairs(static_cast<std::size_t>(p), xi, ng0, ng1, ng2, ng3);
      std::memcpy(&dnp[p], &dn, sizeof(F4));
      const F4 g = __builtin_shufflevector(__builtin_shufflevector(ng0, ng1, 3, 7, 3, 7),
                                           __builtin_shufflevector(ng2, ng3, 3, 7, 3, 7), 0, 1,
                                           4, 5);
      const F4 div = g * dn;
      si += div[0];
      s[kr[p].j] += div[0];
      si += div[1];
      s[kr[p + 1].j] += div[1];
      si += div[2];
      s[kr[p + 2].j] += div[2];
      si += div[3];
      s[kr[p + 3].j] += div[3];
    }
    for (; p + 1 < rn[i + 1]; p += 2) {
      const PairKernel& e0 = kr[p];
      const PairKernel& e1 = kr[p + 1];
      F4 ng0, ng1;
      float dn0, dn1;
      two_pairs(static_cast<std::size_t>(p), xi, ng0, ng1, dn0, dn1);
      dnp[p] = dn0;
      dnp[p + 1] = dn1;
      const float div0 = e0.g * dn0, div1 = e1.g * dn1;
      si += div0;
      s[e0.j] += div0;
      si += div1;
      s[e1.j] += div1;
    }
    if (p < rn[i + 1]) {
      const PairKernel& e = kr[p];
      F4 ng;
      std::memcpy(&ng, &e, sizeof(F4));
      const float dn = dot3(ng, xf[e.j] - xi);
      dnp[p] = dn;
      const float div = e.g * dn;
      si += div;
      s[e.j] += div;
    }
    s[i] += si;
    // Far pairs of row i sit at [cap - rf[i+1], cap - rf[i]); their gradient lane is 0.
    F4 yi = F4{0.0f, 0.0f, 0.0f, 0.0f};
    std::size_t q = cap - rf[i + 1];
    const std::size_t q_end = cap - rf[i];
    for (; q + 3 < q_end; q += 4) {
      F4 n0, n1, n2, n3;
      const F4 dn = four_pairs(q, xi, n0, n1, n2, n3);
      const F4 f0 = (kr[q].a * dn[0]) * n0;
      yi -= f0;
      yf[kr[q].j] += f0;
      const F4 f1 = (kr[q + 1].a * dn[1]) * n1;
      yi -= f1;
      yf[kr[q + 1].j] += f1;
      const F4 f2 = (kr[q + 2].a * dn[2]) * n2;
      yi -= f2;
      yf[kr[q + 2].j] += f2;
      const F4 f3 = (kr[q + 3].a * dn[3]) * n3;
      yi -= f3;
      yf[kr[q + 3].j] += f3;
    }
    for (; q + 1 < q_end; q += 2) {
      const PairKernel& e0 = kr[q];
      const PairKernel& e1 = kr[q + 1];
      F4 n0, n1;
      float dn0, dn1;
      two_pairs(q, xi, n0, n1, dn0, dn1);
      const F4 f0 = (e0.a * dn0) * n0;
      yi -= f0;
      yf[e0.j] += f0;
      const F4 f1 = (e1.a * dn1) * n1;
      yi -= f1;
      yf[e1.j] += f1;
    }
    if (q < q_end) {
      const PairKernel& e = kr[q];
      F4 n;
      std::memcpy(&n, &e, sizeof(F4));
      const F4 f = (e.a * dot3(n, xf[e.j] - xi)) * n;
      yi -= f;
      yf[e.j] += f;
    }
    yf[i] += yi;
  }
  // Near pairs, second pass: the viscous and bond force a dn n together with the gradient
  // pass of the pressure, y += sum_k coef_k (grad C_k . x) grad C_k, in one scattered update.
  // (The forces' last lane carries coef * g: never read.)
  const double* pc = press_coef_.data();
  for (std::size_t k = 0; k < span; ++k) {
    s[k] = static_cast<float>(s[k] * pc[k]);
    if (k < walled && slot[k] >= 0) y[k] += static_cast<double>(s[k]) * wall_g_[slot[k]];
  }
  for (std::size_t i = 0; i < rows; ++i) {
    const float si = s[i];
    F4 yi = F4{0.0f, 0.0f, 0.0f, 0.0f};
    for (std::int32_t p = rn[i]; p < rn[i + 1]; ++p) {
      const PairKernel& e = kr[p];
      F4 ng;
      std::memcpy(&ng, &e, sizeof(F4));
      const F4 f = (e.a * dnp[p] + (si + s[e.j]) * e.g) * ng;
      yi -= f;
      yf[e.j] += f;
    }
    yf[i] += yi;
  }
  for (std::size_t k = 0; k < span; ++k)
    y[k] += Vec3(static_cast<double>(yf[k][0]), static_cast<double>(yf[k][1]),
                 static_cast<double>(yf[k][2]));
}

// Filtered, block-Jacobi preconditioned conjugate gradients on the awake particles (Baraff &
// Witkin 1998: the filter removes the constrained components), warm started from the previous
// velocities (the flow changes little between 1 ms ticks).
void Nucleus::solve(NumericalReport& report) {
  const std::size_t na = na_;
  Vec3* v = vel_.data();
  Vec3* r = r_.data();
  Vec3* z = z_.data();
  Vec3* p = p_.data();
  Vec3* q = q_.data();
  auto filter = [&](Vec3* u) {
    for (std::size_t c = 0; c < con_particles_; ++c) {
      const std::int32_t k = con_particle_[c];
      for (int a = 0; a < con_count_[c]; ++a) u[k] -= con_e_[c][a] * con_e_[c][a].dot(u[k]);
    }
  };
  // Initial guess: previous velocity with its constrained components replaced; frozen
  // particles hold still (fixed ones move at their prescribed velocity).
  for (std::size_t k = 0; k < na; ++k) v[k] = v_[lg_[k]];
  for (std::size_t c = 0; c < con_particles_; ++c) {
    const std::int32_t k = con_particle_[c];
    Vec3 u = v[k];
    for (int a = 0; a < con_count_[c]; ++a) u -= con_e_[c][a] * con_e_[c][a].dot(u);
    v[k] = u + con_v_[c];
  }
  for (std::size_t k = na; k < nl_; ++k) {
    const std::int32_t i = lg_[k];
    v[k] = fixed_[i] ? fixed_v_[i] : Vec3::Zero();
  }
  for (const std::int32_t i : fixed_list_) v_[i] = fixed_v_[i];
  apply(v, q, frozen_moving_);
  // A v on the constrained rows, kept along with v (A v0 + sum alpha A p): the contact forces
  // are its constrained part (reactions_and_pressure), which the filtered residual drops.
  for (std::size_t c = 0; c < con_particles_; ++c) con_av_[c] = q[con_particle_[c]];
  double b_norm2 = 0.0, g_norm2 = 0.0;
  const double g2 = gravity_.squaredNorm();
  for (std::size_t k = 0; k < na; ++k) {
    r[k] = rhs_[k] - q[k];
    b_norm2 += rhs_[k].squaredNorm();
    g_norm2 += mass_l_[k] * mass_l_[k] * g2;
  }
  filter(r);
  // Tolerance relative to the right-hand side, but never below the weight impulse scale: at
  // rest the right-hand side cancels almost exactly and a purely relative test would ask for
  // round-off.
  const double scale = std::sqrt(std::max(b_norm2, g_norm2 * solver_.dt_s * solver_.dt_s));
  const double tol = solver_.tolerance * scale;
  double rz = 0.0;
  double r_norm = 0.0;
  for (std::size_t k = 0; k < na; ++k) z[k] = mul(diag_inv_[k], r[k]);
  filter(z);
  for (std::size_t k = 0; k < na; ++k) {
    p[k] = z[k];
    rz += r[k].dot(z[k]);
    r_norm += r[k].squaredNorm();
  }
  // The iterations apply only pairs with an awake particle: p is zero on the halo.
  for (std::size_t k = na; k < nh_; ++k) p[k] = Vec3::Zero();
  r_norm = std::sqrt(r_norm);
  int it = 0;
  const int max_it = std::max(1, solver_.max_iterations);
  while (r_norm > tol && it < max_it) {
    apply(p, q, false);
    for (std::size_t c = 0; c < con_particles_; ++c) con_aq_[c] = q[con_particle_[c]];
    filter(q);
    double pq = 0.0;
    for (std::size_t k = 0; k < na; ++k) pq += p[k].dot(q[k]);
    if (!(pq > 0.0)) break;  // converged to round-off (or a non-finite value, caught later)
    const double alpha = rz / pq;
    for (std::size_t c = 0; c < con_particles_; ++c) con_av_[c] += alpha * con_aq_[c];
    double rz_new = 0.0;
    double rn = 0.0;
    // r stays filtered (q is), so r . z equals r . (filtered z): the dot product is taken
    // before the filter.
    for (std::size_t k = 0; k < na; ++k) {
      v[k] += alpha * p[k];
      r[k] -= alpha * q[k];
      rn += r[k].squaredNorm();
      z[k] = mul(diag_inv_[k], r[k]);
      rz_new += r[k].dot(z[k]);
    }
    r_norm = std::sqrt(rn);
    ++it;
    if (r_norm <= tol) break;
    filter(z);
    const double beta = rz_new / rz;
    rz = rz_new;
    for (std::size_t k = 0; k < na; ++k) p[k] = z[k] + beta * p[k];
  }
  for (std::size_t k = 0; k < na; ++k) v_[lg_[k]] = v[k];
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
  const Vec3* v = vel_.data();
  const std::size_t rows = frozen_moving_ ? nl_ : nh_;
  // Divergence of the solved velocity (relative to moving walls): C at the end of the step is
  // C + dt * s, and the pressure kappa * that.
  for (std::size_t k = 0; k < rows; ++k) s_[k] = 0.0;
  for (std::size_t w = 0; w < wall_particles_; ++w) {
    const std::int32_t k = wall_particle_[w];
    s_[k] = wall_g_[w].dot(v[k]);
  }
  for (std::size_t w = 0; w < wall_count_; ++w) {
    const WallHit& hit = walls_[w];
    s_[hit.particle] -= hit.grad.dot(hit.v_wall);
  }
  // Row by row (the near pairs [0, near_awake_) or [0, near_) are rows [0, na) or [0, nh)),
  // the first end's sum in a register: it is complete from the earlier rows when its own row
  // starts, and no later row reaches it, so the additions are the same in the same order.
  {
    const std::size_t near_rows = frozen_moving_ ? nh_ : na_;
    const std::int32_t* rn = row_near_.data();
    const std::int32_t* pj = pair_j_.data();
    const double* pg = pair_g_.data();
    const Vec3* pn = pair_n_.data();
    double* s = s_.data();
    for (std::size_t i = 0; i < near_rows; ++i) {
      const Vec3 vi = v[i];
      double si = s[i];
      for (std::int32_t p = rn[i]; p < rn[i + 1]; ++p) {
        const std::int32_t j = pj[p];
        const double div = pg[p] * pn[p].dot(v[j] - vi);
        si += div;
        s[j] += div;
      }
      s[i] = si;
    }
  }
  for (std::size_t k = 0; k < nh_; ++k) {
    const std::int32_t i = lg_[k];
    pressure_[i] = press_coef_[k] > 0.0
                       ? std::max(0.0, kappa_[i] * (constraint_[k] + dt * s_[k]))
                       : 0.0;
  }
  // Contact forces: the constrained part of A v - b, divided by dt (A v kept by solve()).
  std::size_t w0 = 0;
  while (w0 < wall_count_) {
    // The hits of one particle are consecutive.
    const std::int32_t k = walls_[w0].particle;
    const std::int32_t i = lg_[k];
    std::size_t end = w0;
    while (end < wall_count_ && walls_[end].particle == k) ++end;
    // Split the constraint force over this particle's contacts: lambda = sum_a a_k n_k.
    double share[kMaxWallHitsPerParticle] = {0, 0, 0, 0};
    const std::int32_t cs = k < static_cast<std::int32_t>(na_) ? con_slot_[k] : -1;
    if (cs >= 0) {
      Vec3 lambda = (con_av_[cs] - rhs_[k]) / dt;
      Vec3 constrained = Vec3::Zero();
      for (int a = 0; a < con_count_[cs]; ++a)
        constrained += con_e_[cs][a] * con_e_[cs][a].dot(lambda);
      lambda = constrained;
      int idx[3];
      int nc = 0;
      for (std::size_t h = w0; h < end && nc < 3; ++h)
        if (walls_[h].contact) idx[nc++] = static_cast<int>(h - w0);
      if (nc == 1) {
        share[idx[0]] = lambda.dot(walls_[w0 + idx[0]].normal);
      } else if (nc > 1) {
        Eigen::Matrix3d G = Eigen::Matrix3d::Identity();
        Vec3 rhs = Vec3::Zero();
        for (int a = 0; a < nc; ++a) {
          rhs[a] = walls_[w0 + idx[a]].normal.dot(lambda);
          for (int b = 0; b < nc; ++b)
            G(a, b) = walls_[w0 + idx[a]].normal.dot(walls_[w0 + idx[b]].normal);
        }
        const Vec3 sol = G.ldlt().solve(rhs);
        for (int a = 0; a < nc; ++a) share[idx[a]] = std::isfinite(sol[a]) ? sol[a] : 0.0;
      }
      // A wall that pulls (negative share) lets go next step.
      for (int a = 0; a < nc; ++a)
        if (share[idx[a]] < 0.0) release_[i] = 1;
    }
    for (std::size_t h = w0; h < end; ++h) {
      const WallHit& w = walls_[h];
      if (w.collider < 0) {
        // The gathered static (the bone): the same three parts, only recorded.
        if (w.collider == -1 - options_.gathered_static) {
          Vec3 f = -share[h - w0] * w.normal;
          f += (visc_coef_[k] * w.visc) * (v[k] - w.v_wall);
          f += volume_ * pressure_[i] * w.grad;
          static_force_[i] += f;
        }
        continue;
      }
      const Collider& c = moving[w.collider];
      if (c.body < 0 || static_cast<std::size_t>(c.body) >= reactions.size()) continue;
      BodyReaction& r = reactions[c.body];
      // Force on the body = minus the force on the particle.
      Vec3 f = -share[h - w0] * w.normal;                // contact
      const Eigen::Matrix3d C = visc_coef_[k] * w.visc;
      f += C * (v[k] - w.v_wall);                        // no-slip drag
      f += volume_ * pressure_[i] * w.grad;              // wall pressure (grad points inward)
      r.force_N += f;
      body_force_[i] += f;
      const Vec3 arm = w.point - r.reference_point;
      r.torque_Nm += arm.cross(f);
      // Trace: an upper bound of the largest eigenvalue of the (PSD) coupling tensor.
      r.drag_Ns_m += C.trace();
      r.rot_drag_Nms += C.trace() * arm.squaredNorm();
    }
    w0 = end;
  }
}

// Positions, then the swept contact projection: each particle path is followed in the
// collider's frame from its start-of-step pose to its end-of-step pose; a path that enters the
// (h/2-inflated) solid is stopped on the side it came from. A collider whose surface was
// beyond the wall range at the start of the step is skipped when the path (relative to the
// collider) is shorter than the gap: the path cannot reach the inflated surface.
void Nucleus::integrate_and_project(double dt, std::span<const Collider> moving,
                                    std::span<BodyReaction> reactions) {
  for (const std::int32_t i : fixed_list_) x_[i] += dt * fixed_v_[i];
  for (std::size_t k = 0; k < na_; ++k) {
    const std::int32_t i = lg_[k];
    x_[i] += dt * v_[i];
  }
  const std::size_t n_static = statics_.size();
  const double tiny = 1e-4 * h_;
  const double wall_range = radius_ + 0.5 * h_;
  const double free_path = wall_range - contact_ - 0.01 * h_;
  std::size_t hit_cursor = 0;  // walls_ holds each particle's hits consecutively, by local index
  const std::uint32_t static_bits = n_static >= 32 ? ~0u : ((1u << n_static) - 1u);
  for (std::size_t k = 0; k < na_; ++k) {
    const std::int32_t i = lg_[k];
    const std::uint32_t near_mask = near_colliders_[k];
    const bool check_all = all_colliders_[k] != 0;
    while (hit_cursor < wall_count_ && walls_[hit_cursor].particle < static_cast<std::int32_t>(k))
      ++hit_cursor;
    std::size_t hit_end = hit_cursor;
    while (hit_end < wall_count_ && walls_[hit_end].particle == static_cast<std::int32_t>(k))
      ++hit_end;
    double moved = (x_[i] - x_start_[i]).norm();  // kept current as projections move x
    // Statics, then the moving bodies, then the statics again: a particle squeezed between
    // the instrument and a wall ends on the wall's side (walls and bone are never crossed; an
    // overlap with the instrument is pushed out over the next steps).
    const std::size_t n_all = n_static + moving.size();
    // The statics' second round sees the same position, path and hits as their first when no
    // collider moved the particle in between: it would find nothing either (skipped).
    bool projected = false;
    const std::size_t n_pass = n_all + (moving.empty() ? 0 : n_static);
    // The first pass from `pass` on that can find anything: a static collider the particle was
    // not near is skipped below while its path (the particle's own displacement, the same for
    // every static) is free, so those passes are stepped over at once with the near mask.
    auto next_pass = [&](std::size_t pass) -> std::size_t {
      if (check_all || !(moved < free_path)) return pass;
      const std::size_t base = pass < n_all ? 0 : n_all;
      const std::size_t c_idx = pass - base;
      if (c_idx >= n_static) return pass;
      const std::uint32_t rest = near_mask & static_bits & (~0u << c_idx);
      return rest ? base + static_cast<std::size_t>(__builtin_ctz(rest)) : base + n_static;
    };
    for (std::size_t pass = next_pass(0); pass < n_pass; pass = next_pass(pass + 1)) {
      if (pass >= n_all && !projected) break;
      const std::size_t c_idx = pass < n_all ? pass : pass - n_all;
      const bool is_static = c_idx < n_static;
      const Collider& c = is_static ? statics_[c_idx] : moving[c_idx - n_static];
      if (!check_all && !(near_mask & (1u << c_idx))) {
        // Path length in the collider's frame: the particle's displacement plus how far the
        // collider's material near it moved (|v| dt + |w| dt * distance).
        double path = moved;
        if (!is_static)
          path += (frame_lin_speed_[c_idx] +
                   frame_ang_speed_[c_idx] * (x_start_[i] - c.pose.position).norm()) *
                  dt * 1.01;
        if (path < free_path) continue;
      }
      const Pose& start = c.pose;
      const Pose& end = is_static ? c.pose : end_pose_[c_idx - n_static];
      const bool start_unrotated = frame_identity_[c_idx] != 0;
      const bool end_unrotated = is_static ? start_unrotated : end_identity_[c_idx - n_static] != 0;
      const Vec3 p0 = to_local(start, start_unrotated, x_start_[i]);
      Vec3 p1 = to_local(end, end_unrotated, x_[i]);
      const double len = (p1 - p0).norm();
      // The start distance is the one setup_walls found for this particle's hit on c (the same
      // evaluation). For an exact distance (1-Lipschitz: not the sampled bone) a path shorter
      // than d0 - contact - 2 tiny can neither end inside nor cross the inflated surface, the
      // test below would pass: skip both distances.
      const std::int32_t hit_id = is_static ? -1 - static_cast<std::int32_t>(c_idx)
                                            : static_cast<std::int32_t>(c_idx - n_static);
      std::size_t h = hit_cursor;
      while (h < hit_end && walls_[h].collider != hit_id) ++h;
      const bool known = h < hit_end;
      if (known && c.kind != ColliderKind::kSdfGrid &&
          len <= walls_[h].distance - contact_ - 2.0 * tiny)
        continue;
      Vec3 n1;
      const double d1 = signed_distance_local(c, p1, &n1);
      Vec3 n0;
      const double d0 = known ? walls_[h].distance : signed_distance_local(c, p0, &n0);
      // The path cannot reach the inflated surface (triangle inequality on distances).
      if (d1 >= contact_ - tiny && len <= d0 + d1 - 2.0 * contact_) continue;
      Vec3 normal;   // local normal of the face the particle is held on
      Vec3 surface;  // a local point of that face
      bool hit = false;
      if (d0 < contact_) {
        // Started in contact: the exit side is the start side.
        if (d1 >= contact_ - tiny) continue;
        if (known) signed_distance_local(c, p0, &n0);  // the start normal, in the local frame
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
      moved = (x_[i] - x_start_[i]).norm();
      projected = true;
      // Remove the approaching normal velocity relative to the surface; its impulse is a
      // force on the collider's body.
      const Vec3 nw = end.orientation * normal;
      const Vec3 vw = is_static ? Vec3::Zero() : moving[c_idx - n_static].velocity_at(x_[i]);
      const double vn = (v_[i] - vw).dot(nw);
      if (vn < 0.0) {
        v_[i] -= vn * nw;
        if (is_static) {
          if (static_cast<int>(c_idx) == options_.gathered_static)
            static_force_[i] += mass_[i] * vn / dt * nw;
        } else {
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
    for (std::size_t k = 0; k < na_; ++k) {
      const std::int32_t i = lg_[k];
      x_[i][a] = lo + (x_[i][a] - lo) - L * std::floor((x_[i][a] - lo) / L);
    }
  }
}

// Bonds break when their force exceeds k * delta_max, i.e. |stretch| > delta_max
// (seed Eq. 9-10). Only bonds of awake or fixed particles can have changed length.
void Nucleus::break_bonds() {
  auto test = [&](std::int32_t b) {
    if (!bond_alive_[b]) return;
    const std::int32_t i = bond_ij_[2 * b], j = bond_ij_[2 * b + 1];
    // |r - L| > delta  <=>  r^2 > (L + delta)^2 or r^2 < (L - delta)^2 (the latter only
    // when L > delta): no square root per bond. An unbreakable bond (delta <= 0) has the
    // bounds +inf and 0, which no r^2 passes, so it needs no test of its own.
    const double r2 = min_image(x_[j] - x_[i]).squaredNorm();
    if (r2 > bond_break_hi2_[b] || r2 < bond_break_lo2_[b]) {
      bond_alive_[b] = 0;
      ++broken_;
      for (const std::int32_t e : {i, j}) {
        if (fixed_[e] || wake_next_[e]) continue;
        wake_next_[e] = 1;
        wake_list_[wake_count_++] = e;
      }
    }
  };
  // Every live bond of an awake particle is carried by exactly one of this step's pairs with
  // an awake particle (it was shorter than R at the start) or is a loose bond.
  for (std::size_t p = 0; p < near_awake_; ++p)
    if (pair_bond_[p] >= 0) test(pair_bond_[p]);
  for (std::size_t p = pair_cap_ - far_awake_; p < pair_cap_; ++p)
    if (pair_bond_[p] >= 0) test(pair_bond_[p]);
  for (std::size_t k = 0; k < loose_bonds_; ++k) test(loose_[k]);
  // Fixed particles move too: all their bonds (one shared with an awake particle is tested
  // again, with the same result).
  for (const std::int32_t u : fixed_list_)
    for (std::int32_t a = bond_adj_start_[u]; a < bond_adj_start_[u + 1]; ++a) test(bond_adj_[a]);
}

}  // namespace acdr
