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
#include "engine/nucleus/neighbor_grid.hpp"

namespace acdr {
namespace {

constexpr int kCalmStepsToSleep = 20;   // steps below the sleep speed before sleeping
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
{
  model_.config = config;
  model_.solver = solver;
  model_.options = options;
  model_.gravity = gravity_m_s2;
  model_.h = config.spacing_m;
  const double contact = options.contact_radius_factor * model_.h;
  // Lattice points at min + (i + 1/2) h: a block that fills a box touches its walls at h/2.
  NucleusParticleSetup setup;
  for (const auto& block : config.blocks) {
    Eigen::Vector3i n;
    for (int a = 0; a < 3; ++a)
      n[a] = std::max(1, static_cast<int>(std::lround((block.max_m[a] - block.min_m[a]) / model_.h)));
    for (int k = 0; k < n.z(); ++k)
      for (int j = 0; j < n.y(); ++j)
        for (int i = 0; i < n.x(); ++i) {
          const Vec3 p = block.min_m + model_.h * Vec3(i + 0.5, j + 0.5, k + 0.5);
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
  const double bond_r = config.bond_radius_factor * model_.h;
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
{
  model_.config = config;
  model_.solver = solver;
  model_.options = options;
  model_.gravity = gravity_m_s2;
  model_.h = config.spacing_m;
  NucleusParticleSetup copy = setup;
  if (!options.bonds_enabled) copy.bonds.clear();
  init(static_colliders, copy);
}

void Nucleus::init(std::span<const Collider> static_colliders,
                   const NucleusParticleSetup& setup) {
  assert(model_.h > 0.0 && "nucleus spacing must be positive");
  model_.statics.assign(static_colliders.begin(), static_colliders.end());
  if (model_.config.materials.empty()) model_.config.materials.emplace_back();
  model_.volume = model_.h * model_.h * model_.h;
  model_.radius = model_.options.neighbor_radius_factor * model_.h;
  model_.density_radius = std::min(model_.options.density_radius_factor * model_.h, model_.radius);
  model_.contact = model_.options.contact_radius_factor * model_.h;

  // Rest sums of the full cubic lattice: the normalisations n0 (density) and s0 (viscosity).
  model_.n0 = 1.0;
  model_.s0 = 0.0;
  model_.t0 = 0.0;
  model_.sites.offset.clear();
  model_.sites.w.clear();
  model_.sites.r2.clear();
  model_.sites.wv.clear();
  model_.sites.len.clear();
  model_.sites.uu.clear();
  const int m = static_cast<int>(std::ceil(model_.options.neighbor_radius_factor));
  for (int a = -m; a <= m; ++a)
    for (int b = -m; b <= m; ++b)
      for (int c = -m; c <= m; ++c) {
        if (a == 0 && b == 0 && c == 0) continue;
        const double r = model_.h * std::sqrt(double(a * a + b * b + c * c));
        if (r >= model_.radius) continue;
        const double wv = viscous_weight(r, model_.radius);
        model_.n0 += kernel(r, model_.density_radius);
        model_.s0 += wv * r * r;
        model_.t0 += wv * (a * model_.h) * (a * model_.h) * (c * model_.h) * (c * model_.h) / (r * r);
        model_.sites.offset.push_back(model_.h * Vec3(a, b, c));
        model_.sites.w.push_back(kernel(r, model_.density_radius));
        model_.sites.wv.push_back(wv);
        model_.sites.r2.push_back(r * r);
        model_.sites.len.push_back(r);
        const Vec3 u = model_.h * Vec3(a, b, c) / r;
        model_.sites.uu.push_back(u * u.transpose());
      }

  build_wall_table();

  const std::size_t n = setup.positions_m.size();
  state_.x = setup.positions_m;
  state_.v.assign(n, Vec3::Zero());
  if (setup.velocities_m_s.size() == n) state_.v = setup.velocities_m_s;
  work_.step.x_start = state_.x;
  state_.f_ext.assign(n, Vec3::Zero());
  state_.fixed_v.assign(n, Vec3::Zero());
  model_.material.assign(n, 0);
  if (setup.materials.size() == n) model_.material = setup.materials;
  model_.fixed.assign(n, 0);
  if (setup.fixed.size() == n) model_.fixed = setup.fixed;
  model_.mass.resize(n);
  model_.mu.resize(n);
  model_.kappa.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    model_.material[i] = static_cast<std::uint8_t>(
        std::min<std::size_t>(model_.material[i], model_.config.materials.size() - 1));
    const MaterialConfig& mat = model_.config.materials[model_.material[i]];
    model_.mass[i] = mat.density_kg_m3 * model_.volume;
    model_.mu[i] = mat.viscosity_Pa_s;
    model_.kappa[i] = mat.bulk_modulus_Pa;
  }
  state_.awake.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) state_.awake[i] = model_.fixed[i] ? 0 : 1;
  state_.wake_next.assign(n, 0);
  state_.calm.assign(n, 0);
  state_.release.assign(n, 0);
  state_.pressure.assign(n, 0.0);
  state_.body_force.assign(n, Vec3::Zero());
  state_.active.assign(n, 0);
  state_.active_count = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (state_.awake[i]) state_.active[state_.active_count++] = static_cast<std::int32_t>(i);
  model_.fixed_list.clear();
  for (std::size_t i = 0; i < n; ++i)
    if (model_.fixed[i]) model_.fixed_list.push_back(static_cast<std::int32_t>(i));
  state_.wake_list.assign(n, 0);
  state_.wake_count = 0;
  work_.stamp.assign(n, 0);

  const std::size_t nb = setup.bonds.size();
  model_.bonds.ij.resize(2 * nb);
  model_.bonds.rest.resize(nb);
  model_.bonds.k.resize(nb);
  model_.bonds.break_stretch.resize(nb);
  state_.bond_alive.assign(nb, 1);
  work_.loose.in_pair.assign(nb, 0);
  for (std::size_t b = 0; b < nb; ++b) {
    const auto& bond = setup.bonds[b];
    assert(bond.i >= 0 && bond.j >= 0 && std::size_t(bond.i) < n && std::size_t(bond.j) < n);
    model_.bonds.ij[2 * b] = bond.i;
    model_.bonds.ij[2 * b + 1] = bond.j;
    model_.bonds.rest[b] = bond.rest_length_m >= 0.0 ? bond.rest_length_m
                                              : (state_.x[bond.j] - state_.x[bond.i]).norm();
    model_.bonds.k[b] = bond.stiffness_N_m;
    model_.bonds.break_stretch[b] = bond.break_stretch_m;
  }
  // Squared lengths at which each bond breaks (break_bonds), 0 and +inf when unbreakable.
  model_.bonds.break_hi2.assign(nb, std::numeric_limits<double>::infinity());
  model_.bonds.break_lo2.assign(nb, 0.0);
  for (std::size_t b = 0; b < nb; ++b) {
    if (model_.bonds.break_stretch[b] <= 0.0) continue;
    const double hi = model_.bonds.rest[b] + model_.bonds.break_stretch[b], lo = model_.bonds.rest[b] - model_.bonds.break_stretch[b];
    model_.bonds.break_hi2[b] = hi * hi;
    model_.bonds.break_lo2[b] = lo > 0.0 ? lo * lo : 0.0;
  }
  model_.periodic = model_.options.periodic[0] || model_.options.periodic[1] || model_.options.periodic[2];
  model_.bonds.loose_possible = false;
  for (std::size_t b = 0; b < nb; ++b)
    if (model_.bonds.break_stretch[b] <= 0.0 || model_.bonds.rest[b] + model_.bonds.break_stretch[b] >= model_.radius) model_.bonds.loose_possible = true;
  // Bonds of each particle (CSR), in bond order.
  model_.bonds.adj_start.assign(n + 1, 0);
  for (std::size_t b = 0; b < nb; ++b) {
    ++model_.bonds.adj_start[model_.bonds.ij[2 * b] + 1];
    ++model_.bonds.adj_start[model_.bonds.ij[2 * b + 1] + 1];
  }
  for (std::size_t i = 0; i < n; ++i) model_.bonds.adj_start[i + 1] += model_.bonds.adj_start[i];
  model_.bonds.adj.assign(2 * nb, 0);
  {
    std::vector<std::int32_t> cursor(model_.bonds.adj_start.begin(), model_.bonds.adj_start.end() - 1);
    for (std::size_t b = 0; b < nb; ++b) {
      model_.bonds.adj[cursor[model_.bonds.ij[2 * b]]++] = static_cast<std::int32_t>(b);
      model_.bonds.adj[cursor[model_.bonds.ij[2 * b + 1]]++] = static_cast<std::int32_t>(b);
    }
  }
  work_.loose.bond.assign(nb, 0);
  work_.loose.ij.assign(2 * nb, 0);
  work_.loose.n.assign(nb, Vec3::Zero());
  work_.loose.a.assign(nb, 0.0);

  // Fixed capacities: nothing below allocates during step().
  model_.skin = model_.options.skin_factor * model_.h;
  std::size_t lattice = 0;  // lattice sites within R + skin
  {
    const double reach = model_.options.neighbor_radius_factor + model_.options.skin_factor;
    const int mm = static_cast<int>(std::ceil(reach));
    for (int a = -mm; a <= mm; ++a)
      for (int b = -mm; b <= mm; ++b)
        for (int c = -mm; c <= mm; ++c)
          if (a * a + b * b + c * c > 0 && a * a + b * b + c * c < reach * reach) ++lattice;
  }
  work_.rows.grid.reserve(std::max<std::size_t>(n, 1));
  work_.rows.x_built.assign(n, Vec3::Zero());
  work_.rows.grid_valid = false;
  work_.rows.epoch = 0;
  work_.rows.epoch_of.assign(n, 0);
  work_.rows.start.assign(n, 0);
  work_.rows.len.assign(n, 0);
  // Every particle's row once per grid build, with room for 50 % compression.
  const std::size_t row_cap = std::max<std::size_t>(64, n * (lattice * 3 / 2 + 8));
  work_.rows.j.assign(row_cap, 0);
  work_.rows.bond.assign(row_cap, -1);
  work_.rows.scratch_j.assign(4 * lattice + 64, 0);
  work_.rows.scratch_bond.assign(4 * lattice + 64, 0);
  work_.rows.scratch_bucket.assign(4 * lattice + 64, 0);
  work_.rows.scratch_r2.assign(4 * lattice + 64, 0.0f);
  work_.rows.upper.assign(n, 0);
  work_.rows.beyond.assign(n, 0);
  work_.rows.r2.assign(row_cap, 0.0f);
  work_.rows.used = 0;
  work_.rows.partner_bond.assign(n, -1);

  work_.step.local.assign(n, -1);
  work_.step.global.assign(n, 0);
  work_.step.awake_end = work_.step.halo_end = work_.step.outer_end = 0;
  work_.pairs.cap = std::max<std::size_t>(16, n * std::max<std::size_t>(model_.options.max_neighbors, 1) / 2);
  work_.pairs.i.assign(work_.pairs.cap, 0);
  work_.pairs.j.assign(work_.pairs.cap, 0);
  work_.pairs.n.assign(work_.pairs.cap, Vec3::Zero());
  work_.pairs.r.assign(work_.pairs.cap, 0.0);
  work_.pairs.wv.assign(work_.pairs.cap, 0.0);
  work_.pairs.g.assign(work_.pairs.cap, 0.0);
  work_.pairs.bond.assign(work_.pairs.cap, -1);
  work_.pairs.kernel.assign(work_.pairs.cap, PairKernel{0.0f, 0.0f, 0.0f, 0.0f, 0, 0.0f});
  work_.apply.dn.assign(work_.pairs.cap, 0.0f);
  work_.apply.x.assign(n, F4{0.0f, 0.0f, 0.0f, 0.0f});
  work_.apply.y.assign(n, F4{0.0f, 0.0f, 0.0f, 0.0f});
  work_.apply.s.assign(n, 0.0f);
  work_.pairs.row_near.assign(n + 1, 0);
  work_.pairs.row_far.assign(n + 1, 0);

  work_.sys.second_moment.assign(n, 0.0);
  work_.sys.density.assign(n, 0.0);
  work_.sys.constraint.assign(n, 0.0);
  work_.sys.press_coef.assign(n, 0.0);
  work_.sys.visc_coef.assign(n, 0.0);
  work_.sys.press_force.assign(n, 0.0);
  work_.sys.half_visc.assign(n, 0.0);
  work_.sys.mass.assign(n, 0.0);
  work_.sys.rhs.assign(n, Vec3::Zero());
  work_.sys.diag_inv.assign(n, {1, 1, 1, 0, 0, 0});
  work_.pcg.v.assign(n, Vec3::Zero());
  work_.pcg.r.assign(n, Vec3::Zero());
  work_.pcg.z.assign(n, Vec3::Zero());
  work_.pcg.p.assign(n, Vec3::Zero());
  work_.pcg.q.assign(n, Vec3::Zero());
  work_.sys.div.assign(n, 0.0);
  work_.walls.particle.assign(n, 0);
  work_.walls.c.assign(n, Eigen::Matrix3d::Zero());
  work_.walls.g.assign(n, Vec3::Zero());
  work_.walls.slot.assign(n, -1);
  work_.walls.particles = 0;
  work_.contacts.particle.assign(n, 0);
  work_.contacts.count.assign(n, 0);
  work_.contacts.e.assign(n, {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()});
  work_.contacts.v.assign(n, Vec3::Zero());
  work_.contacts.slot.assign(n, -1);
  work_.contacts.av.assign(n, Vec3::Zero());
  work_.contacts.aq.assign(n, Vec3::Zero());
  work_.contacts.particles = 0;
  work_.cull.near_colliders.assign(n, 0);
  work_.cull.all_colliders.assign(n, 0);
  work_.cull.static_ref.assign(n, Vec3::Constant(std::numeric_limits<double>::quiet_NaN()));
  work_.cull.static_mask.assign(n, 0);
  work_.walls.hits.resize(kMaxWallHitsPerParticle * n + 16);
  work_.site_cache.entries.assign(kMaxWallHitsPerParticle * n, SiteSums{});
  work_.site_cache.next.assign(n, 0);
  work_.frames.site_local.assign(32 * model_.sites.offset.size(), Vec3::Zero());
  model_.cache_turn_cos = std::cos(0.5 * model_.solver.wall_sum_cache_tolerance * model_.h / model_.radius);
}

// ------------------------------------------------------------------------------------------
// Accessors

std::size_t Nucleus::particle_count() const { return state_.x.size(); }
std::span<const Vec3> Nucleus::positions() const { return state_.x; }
std::span<const Vec3> Nucleus::velocities() const { return state_.v; }
std::span<const std::uint8_t> Nucleus::materials() const { return model_.material; }
double Nucleus::particle_volume_m3() const { return model_.volume; }
std::size_t Nucleus::bond_count() const { return model_.bonds.rest.size(); }
std::size_t Nucleus::broken_bond_count() const { return state_.broken_bonds; }
std::size_t Nucleus::active_count() const { return state_.active_count; }
const NucleusConfig& Nucleus::config() const { return model_.config; }
std::span<const double> Nucleus::masses() const { return model_.mass; }
std::span<Vec3> Nucleus::external_forces() { return state_.f_ext; }
std::span<const double> Nucleus::pressures() const { return state_.pressure; }
std::span<const Vec3> Nucleus::body_forces() const { return state_.body_force; }
std::span<const std::uint8_t> Nucleus::bond_alive() const { return state_.bond_alive; }
std::span<const std::int32_t> Nucleus::bond_particles() const { return model_.bonds.ij; }
void Nucleus::set_fixed_velocity(std::size_t i, const Vec3& v) { state_.fixed_v[i] = v; }
void Nucleus::set_gravity(const Vec3& g) { model_.gravity = g; }
std::size_t Nucleus::pair_count() const { return work_.pairs.count; }

double Nucleus::kinetic_energy_J() const {
  double e = 0.0;
  for (std::size_t i = 0; i < state_.x.size(); ++i) e += 0.5 * model_.mass[i] * state_.v[i].squaredNorm();
  return e;
}

double Nucleus::mechanical_energy_J() const {
  double e = kinetic_energy_J();
  for (std::size_t i = 0; i < state_.x.size(); ++i) {
    e -= model_.mass[i] * model_.gravity.dot(state_.x[i]);
    if (model_.kappa[i] > 0.0) e += 0.5 * model_.volume * state_.pressure[i] * state_.pressure[i] / model_.kappa[i];
  }
  for (std::size_t b = 0; b < state_.bond_alive.size(); ++b) {
    if (!state_.bond_alive[b]) continue;
    const double stretch =
        min_image(model_, state_.x[model_.bonds.ij[2 * b + 1]] - state_.x[model_.bonds.ij[2 * b]]).norm() - model_.bonds.rest[b];
    e += 0.5 * model_.bonds.k[b] * stretch * stretch;
  }
  return e;
}
double Nucleus::spacing_m() const { return model_.h; }

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
// all bonds.

void Nucleus::step(double dt, std::span<const Collider> moving,
                   std::span<BodyReaction> reactions, NumericalReport& report) {
  report = NumericalReport{};
  assert(moving.size() <= std::size_t(kMaxMovingColliders) && "too many moving colliders");
  assert(model_.statics.size() + moving.size() <= 32 && "collider masks hold 32 colliders");
  assert(dt > 0.0);
  for (auto& r : reactions) {
    r.force_N = Vec3::Zero();
    r.torque_Nm = Vec3::Zero();
    r.drag_Ns_m = 0.0;
    r.rot_drag_Nms = 0.0;
  }
  if (state_.x.empty()) return;
  for (std::size_t m = 0; m < moving.size(); ++m) {
    work_.frames.end_pose[m] = advance(moving[m].pose, moving[m].linear_velocity_m_s,
                           moving[m].angular_velocity_rad_s, dt);
    const Quat& q = work_.frames.end_pose[m].orientation;
    work_.frames.end_identity[m] = q.w() == 1.0 && q.x() == 0.0 && q.y() == 0.0 && q.z() == 0.0;
  }
  // The last step's particles leave the local numbering (and their body forces reset: only
  // they were written).
  for (std::size_t k = 0; k < work_.step.outer_end; ++k) {
    state_.body_force[work_.step.global[k]] = Vec3::Zero();
    work_.step.local[work_.step.global[k]] = -1;
  }
  work_.step.awake_end = work_.step.halo_end = work_.step.outer_end = 0;
  work_.pairs.overflow = false;

  update_grid();
  wake_and_sleep(moving, dt);
  build_pairs();
  if (work_.pairs.overflow) {
    report.ok = false;
    report.stage = "neighbors";
  }
  collider_frames(moving);
  setup_walls(dt, moving);
  assemble(dt);
  solve(report);
  for (std::size_t k = 0; k < state_.active_count; ++k) {
    const Vec3& v = state_.v[state_.active[k]];
    if (!finite(v)) {
      if (report.ok) report.stage = "solve";
      report.ok = false;
      break;
    }
  }
  reactions_and_pressure(dt, moving, reactions);
  integrate_and_project(dt, moving, reactions);
  for (std::size_t k = 0; k < state_.active_count; ++k) {
    const std::size_t i = state_.active[k];
    if (!finite(state_.x[i]) || state_.v[i].squaredNorm() > kMaxSpeed_m_s * kMaxSpeed_m_s) {
      if (report.ok) report.stage = finite(state_.x[i]) ? "speed" : "integrate";
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
// particles move; those that fell asleep keep the displacement they had (work_.rows.frozen_disp2).
void Nucleus::update_grid() {
  double m1 = work_.rows.frozen_disp2[0], m2 = work_.rows.frozen_disp2[1];  // two largest squared displacements
  auto note = [&](std::int32_t i) {
    const double d2 = min_image(model_, state_.x[i] - work_.rows.x_built[i]).squaredNorm();
    if (!(d2 <= m2)) {  // NaN counts as largest
      if (!(d2 <= m1)) {
        m2 = m1;
        m1 = d2;
      } else {
        m2 = d2;
      }
    }
  };
  for (std::size_t k = 0; k < state_.active_count; ++k) note(state_.active[k]);
  for (const std::int32_t i : model_.fixed_list) note(i);
  work_.rows.disp_bound = std::sqrt(m1) + std::sqrt(m2);
  const bool rebuild = !work_.rows.grid_valid || !(work_.rows.disp_bound < model_.skin);
  if (!rebuild) return;
  work_.rows.disp_bound = 0.0;
  work_.rows.frozen_disp2 = {0.0, 0.0};
  work_.rows.grid.build(state_.x, model_.radius + model_.skin, model_.options.periodic, model_.options.periodic_min_m,
              model_.options.periodic_max_m);
  std::copy(state_.x.begin(), state_.x.end(), work_.rows.x_built.begin());
  ++work_.rows.epoch;
  work_.rows.used = 0;
  work_.rows.grid_valid = true;
  ++work_.rows.grid_builds;
  // Re-sort the awake list by particle index (it grows by appending between builds), which
  // keeps the local numbering close to the lattice order.
  if (state_.active_count > 0) {
    std::size_t n_awake = 0;
    for (std::size_t i = 0; i < state_.x.size(); ++i)
      if (state_.awake[i]) state_.active[n_awake++] = static_cast<std::int32_t>(i);
    state_.active_count = n_awake;
  }
}

// Row i: every particle within R + skin of i at the last grid build, with the bond between
// them (-1 if none). Computed at most once per grid build, when i first takes part in a step.
void Nucleus::ensure_row(std::int32_t i) {
  if (work_.rows.epoch_of[i] == work_.rows.epoch) return;
  work_.rows.epoch_of[i] = work_.rows.epoch;
  const double reach = model_.radius + model_.skin;
  const double reach2 = reach * reach;
  // i's bonds by partner (a live bond wins over a broken one between the same particles).
  for (std::int32_t k = model_.bonds.adj_start[i]; k < model_.bonds.adj_start[i + 1]; ++k) {
    const std::int32_t b = model_.bonds.adj[k];
    const std::int32_t other = model_.bonds.ij[2 * b] == i ? model_.bonds.ij[2 * b + 1] : model_.bonds.ij[2 * b];
    if (work_.rows.partner_bond[other] < 0 || !state_.bond_alive[work_.rows.partner_bond[other]]) work_.rows.partner_bond[other] = b;
  }
  const std::size_t start = work_.rows.used;
  const std::size_t cap = work_.rows.j.size();
  const Vec3 xi = work_.rows.x_built[i];
  // Each entry's ordering bucket (see below): higher index first, then lower; within each,
  // inside the density radius, inside R, then beyond (at the build positions).
  const double Rd2 = model_.density_radius * model_.density_radius, R2 = model_.radius * model_.radius;
  const std::size_t scratch = work_.rows.scratch_j.size();
  std::array<std::int32_t, 7> count{};
  work_.rows.grid.for_each_near(xi, [&](std::int32_t j, const Vec3& xj) {
    if (j == i) return;
    const double r2 = min_image(model_, xj - xi).squaredNorm();
    if (!(r2 < reach2)) return;
    if (work_.rows.used >= cap) {
      work_.pairs.overflow = true;
      return;
    }
    const int bucket = (j < i ? 3 : 0) + (r2 < Rd2 ? 0 : (r2 < R2 ? 1 : 2));
    const std::size_t c = work_.rows.used - start;
    if (c < scratch) {
      work_.rows.scratch_bucket[c] = static_cast<std::uint8_t>(bucket);
      work_.rows.scratch_r2[c] = static_cast<float>(r2);
    }
    ++count[bucket + 1];
    work_.rows.j[work_.rows.used] = j;
    work_.rows.bond[work_.rows.used] = work_.rows.partner_bond[j];
    ++work_.rows.used;
  });
  for (std::int32_t k = model_.bonds.adj_start[i]; k < model_.bonds.adj_start[i + 1]; ++k) {
    const std::int32_t b = model_.bonds.adj[k];
    work_.rows.partner_bond[model_.bonds.ij[2 * b] == i ? model_.bonds.ij[2 * b + 1] : model_.bonds.ij[2 * b]] = -1;
  }
  const std::size_t len = work_.rows.used - start;
  work_.rows.start[i] = static_cast<std::int32_t>(start);
  work_.rows.len[i] = static_cast<std::int32_t>(len);
  // Order by bucket (stable counting sort; see work_.rows.upper). A row longer than the scratch is
  // only split into its upper and lower parts (the ordering only saves time).
  std::int32_t upper = 0, beyond = 0;
  if (len <= scratch) {
    std::copy(work_.rows.j.begin() + start, work_.rows.j.begin() + work_.rows.used, work_.rows.scratch_j.begin());
    std::copy(work_.rows.bond.begin() + start, work_.rows.bond.begin() + work_.rows.used, work_.rows.scratch_bond.begin());
    for (int b = 0; b < 6; ++b) count[b + 1] += count[b];
    upper = count[3];
    beyond = count[2];
    for (std::size_t c = 0; c < len; ++c) {
      const std::size_t at = start + count[work_.rows.scratch_bucket[c]]++;
      work_.rows.j[at] = work_.rows.scratch_j[c];
      work_.rows.bond[at] = work_.rows.scratch_bond[c];
      work_.rows.r2[at] = work_.rows.scratch_r2[c];
    }
  } else {
    // Unordered: upper/lower partition only (in place, order within the parts lost).
    std::size_t lo = start, hi = work_.rows.used;
    while (lo < hi) {
      if (work_.rows.j[lo] > i) {
        ++lo;
      } else {
        --hi;
        std::swap(work_.rows.j[lo], work_.rows.j[hi]);
        std::swap(work_.rows.bond[lo], work_.rows.bond[hi]);
      }
    }
    upper = static_cast<std::int32_t>(lo - start);
    beyond = upper;
  }
  work_.rows.upper[i] = upper;
  work_.rows.beyond[i] = beyond;
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
  const std::size_t n = state_.x.size();
  if (!model_.solver.sleep_enabled) {
    // Everything that is not fixed is integrated (the "skip off" case).
    if (state_.active_count + model_.fixed_list.size() != n) {
      state_.active_count = 0;
      for (std::size_t i = 0; i < n; ++i) {
        state_.awake[i] = model_.fixed[i] ? 0 : 1;
        if (state_.awake[i]) state_.active[state_.active_count++] = static_cast<std::int32_t>(i);
      }
    }
    for (std::size_t k = 0; k < state_.wake_count; ++k) state_.wake_next[state_.wake_list[k]] = 0;
    state_.wake_count = 0;
    return;
  }
  const double slow2 = model_.solver.sleep_speed_m_s * model_.solver.sleep_speed_m_s;
  const double sleep_d = model_.solver.sleep_distance_m;
  // Waking first, on the states at the start of the step: particles near a moving collider
  // (marked with this step's stamp, which the awake ones' calm count reads below) and those
  // queued (an awake neighbour moved, a bond broke). New awake particles are kept in work_.step.global
  // (free until build_pairs) and appended to the awake list at the end.
  ++work_.stamp_value;
  const std::int32_t near_mark = work_.stamp_value;
  std::size_t woken = 0;
  auto wake = [&](std::int32_t i) {
    if (model_.fixed[i] || state_.awake[i]) return;
    state_.awake[i] = 1;
    state_.calm[i] = 0;
    work_.step.global[woken++] = i;
  };
  for (const Collider& c : moving) {
    auto test = [&](std::int32_t j) {
      if (work_.stamp[j] == near_mark || model_.fixed[j]) return;
      if (!(signed_distance(c, state_.x[j], nullptr) < sleep_d)) return;
      work_.stamp[j] = near_mark;
      wake(j);
    };
    Vec3 lo, hi;
    if (collider_bounds(c, &lo, &hi)) {
      // The grid holds old positions: the query box is widened by how far they can be off
      // (Up to a skin old: see update_grid.)
      const Vec3 pad = Vec3::Constant(sleep_d + model_.skin);
      work_.rows.grid.for_each_in_box(lo - pad, hi + pad, [&](std::int32_t j, const Vec3&) { test(j); });
    } else {
      for (std::size_t j = 0; j < n; ++j) test(static_cast<std::int32_t>(j));
    }
  }
  const std::size_t was_awake = state_.active_count;
  for (std::size_t k = 0; k < state_.wake_count; ++k) {
    const std::int32_t i = state_.wake_list[k];
    state_.wake_next[i] = 0;
    wake(i);
  }
  state_.wake_count = 0;
  // Particles awake at the start of the step: calm steps, and sleep after enough of them.
  std::size_t survivors = 0;
  for (std::size_t k = 0; k < was_awake; ++k) {
    const std::int32_t i = state_.active[k];
    const bool calm = work_.stamp[i] != near_mark && state_.v[i].squaredNorm() < slow2;
    state_.calm[i] = calm ? static_cast<std::uint16_t>(std::min(state_.calm[i] + 1, 60000)) : 0;
    if (state_.calm[i] >= kCalmStepsToSleep) {
      state_.awake[i] = 0;
      state_.v[i] = Vec3::Zero();
      // Its displacement since the grid build stays in the rebuild test (update_grid).
      const double d2 = min_image(model_, state_.x[i] - work_.rows.x_built[i]).squaredNorm();
      if (d2 > work_.rows.frozen_disp2[1]) {
        work_.rows.frozen_disp2[1] = d2;
        if (work_.rows.frozen_disp2[1] > work_.rows.frozen_disp2[0]) std::swap(work_.rows.frozen_disp2[0], work_.rows.frozen_disp2[1]);
      }
    } else {
      state_.active[survivors++] = i;
    }
  }
  // The awake list stays sorted by particle index (build_pairs relies on it): the woken ones,
  // sorted, are merged in from the back.
  std::sort(work_.step.global.begin(), work_.step.global.begin() + static_cast<std::ptrdiff_t>(woken));
  std::size_t a = survivors, b = woken, out = survivors + woken;
  while (b > 0) {
    if (a > 0 && state_.active[a - 1] > work_.step.global[b - 1]) state_.active[--out] = state_.active[--a];
    else state_.active[--out] = work_.step.global[--b];
  }
  state_.active_count = survivors + woken;
}

// This step's particles in local numbering and their pairs. The awake particles' rows give
// the pairs with an awake particle and, as their sleeping neighbours within R, the halo; the
// halo's rows give the remaining pairs (the halo's densities must be complete) and the outer
// particles. Pairs split by reach: near ones (density radius) from the front of the arrays,
// far ones from the back.
void Nucleus::build_pairs() {
  const double R2 = model_.radius * model_.radius;
  const double Rd2 = model_.density_radius * model_.density_radius;
  const std::size_t cap = work_.pairs.cap;
  work_.pairs.near = work_.pairs.far = 0;
  work_.step.awake_end = state_.active_count;
  for (std::size_t k = 0; k < work_.step.awake_end; ++k) {
    const std::int32_t i = state_.active[k];
    work_.step.global[k] = i;
    work_.step.local[i] = static_cast<std::int32_t>(k);
    work_.step.x_start[i] = state_.x[i];
  }
  work_.step.halo_end = work_.step.awake_end;
  auto emit = [&](std::int32_t li, std::int32_t lj, const Vec3& d, double r2, std::int32_t bond) {
    if (work_.pairs.near + work_.pairs.far >= cap) {
      work_.pairs.overflow = true;
      return;
    }
    const std::size_t p = r2 < Rd2 ? work_.pairs.near++ : cap - 1 - work_.pairs.far++;
    const double r = std::sqrt(r2);
    work_.pairs.i[p] = li;
    work_.pairs.j[p] = lj;
    work_.pairs.r[p] = r;
    work_.pairs.n[p] = d * (1.0 / r);
    if (bond >= 0 && !state_.bond_alive[bond]) bond = -1;
    work_.pairs.bond[p] = bond;
    if (bond >= 0 && model_.bonds.loose_possible) work_.loose.in_pair[bond] = 1;
  };
  // The pairs of local particle k from its row. A neighbour numbered below k was paired from
  // its own side (awake ones before halo ones, halo ones by index; self never appears); one
  // not numbered yet joins the step with the next local number from `next` (the halo for
  // awake particles, the outer ring for halo ones).
  // Starts local particle k's pairs: its Verlet row (built if needed) and where its near and
  // far pairs begin.
  auto open_row = [&](std::size_t k) {
    const std::int32_t i = work_.step.global[k];
    ensure_row(i);
    work_.pairs.row_near[k] = static_cast<std::int32_t>(work_.pairs.near);
    work_.pairs.row_far[k] = static_cast<std::int32_t>(work_.pairs.far);
    return i;
  };
  auto pair_row = [&](std::size_t k, std::size_t& next) {
    const std::int32_t i = open_row(k);
    const std::int32_t* rj = work_.rows.j.data() + work_.rows.start[i];
    const std::int32_t* rb = work_.rows.bond.data() + work_.rows.start[i];
    const Vec3 xi = state_.x[i];
    for (std::int32_t c = 0; c < work_.rows.len[i]; ++c) {
      const std::int32_t j = rj[c];
      std::int32_t lj = work_.step.local[j];
      if (lj >= 0 && lj < static_cast<std::int32_t>(k)) continue;
      const Vec3 d = min_image(model_, state_.x[j] - xi);
      const double r2 = d.squaredNorm();
      if (r2 >= R2 || r2 <= 0.0) continue;
      if (lj < 0) {
        lj = static_cast<std::int32_t>(next++);
        work_.step.local[j] = lj;
        work_.step.global[lj] = j;
      }
      emit(static_cast<std::int32_t>(k), lj, d, r2, rb[c]);
    }
  };
  // Awake rows. The awake list is sorted by particle index, so an awake neighbour numbered
  // below k is exactly an awake neighbour of lower index: the row's upper part (higher
  // indices) is paired whole, its lower part only with particles that are not awake. Rows are
  // ordered by distance within each part, so the range and near/far tests branch alike from
  // row to row.
  const bool propagate_wake = model_.solver.sleep_enabled;
  const double slow2 = model_.solver.sleep_speed_m_s * model_.solver.sleep_speed_m_s;
  // An entry of the upper part's beyond bucket that was at least R + work_.rows.disp_bound away at the
  // build is at least R away now (no particle has moved farther; a 1e-6 relative margin
  // covers the single-precision distances): the range test below would reject it, so it is
  // skipped on its build distance alone. (Periodic domains: not used.)
  // Lower parts pair only the particles that are not awake. When there are few of those, the
  // rows that can hold one are marked from its side, and the others skip their lower part: a
  // non-awake j is in the lower part of row i only if i > j lies in the 27 grid cells around
  // j's build position (the cells are neighbours of each other both ways).
  const std::size_t n_all = state_.x.size();
  const bool mark_lower = (n_all - work_.step.awake_end) * 16 <= work_.step.awake_end;
  std::int32_t lower_mark = 0;
  if (mark_lower) {
    lower_mark = ++work_.stamp_value;
    std::size_t a = 0;
    for (std::size_t j = 0; j < n_all; ++j) {
      const std::int32_t jj = static_cast<std::int32_t>(j);
      if (a < work_.step.awake_end && state_.active[a] == jj) {
        ++a;
        continue;
      }
      work_.rows.grid.for_each_near(work_.rows.x_built[j], [&](std::int32_t i, const Vec3&) {
        if (i > jj) work_.stamp[i] = lower_mark;
      });
    }
  }
  const double reach_now = (model_.radius + work_.rows.disp_bound) * (1.0 + 1e-6);
  const float far2 = model_.periodic ? std::numeric_limits<float>::infinity()
                               : static_cast<float>(reach_now * reach_now * (1.0 + 1e-6));
  for (std::size_t k = 0; k < work_.step.awake_end; ++k) {
    const std::int32_t i = open_row(k);
    const std::int32_t* rj = work_.rows.j.data() + work_.rows.start[i];
    const std::int32_t* rb = work_.rows.bond.data() + work_.rows.start[i];
    const std::int32_t upper = work_.rows.upper[i];
    const Vec3 xi = state_.x[i];
    // Wake propagation for the next step: a frozen neighbour of a moving particle wakes.
    const bool moving_i = propagate_wake && state_.v[i].squaredNorm() >= slow2;
    auto visit = [&](std::int32_t c) {
      const std::int32_t j = rj[c];
      const Vec3 d = min_image(model_, state_.x[j] - xi);
      const double r2 = d.squaredNorm();
      if (r2 >= R2 || r2 <= 0.0) return;
      std::int32_t lj = work_.step.local[j];
      if (lj < 0) {
        lj = static_cast<std::int32_t>(work_.step.halo_end++);
        work_.step.local[j] = lj;
        work_.step.global[lj] = j;
      }
      if (moving_i && lj >= static_cast<std::int32_t>(work_.step.awake_end) && !model_.fixed[j] && !state_.wake_next[j]) {
        state_.wake_next[j] = 1;
        state_.wake_list[state_.wake_count++] = j;
      }
      emit(static_cast<std::int32_t>(k), lj, d, r2, rb[c]);
    };
    const float* rr = work_.rows.r2.data() + work_.rows.start[i];
    const std::int32_t beyond = work_.rows.beyond[i];
    for (std::int32_t c = 0; c < beyond; ++c) visit(c);
    for (std::int32_t c = beyond; c < upper; ++c)
      if (rr[c] < far2) visit(c);
    if (!mark_lower || work_.stamp[i] == lower_mark)
      for (std::int32_t c = upper; c < work_.rows.len[i]; ++c)
        if (!state_.awake[rj[c]]) visit(c);
  }
  work_.pairs.near_awake = work_.pairs.near;
  work_.pairs.far_awake = work_.pairs.far;
  work_.step.outer_end = work_.step.halo_end;
  for (std::size_t k = work_.step.awake_end; k < work_.step.halo_end; ++k) pair_row(k, work_.step.outer_end);
  work_.pairs.row_near[work_.step.halo_end] = static_cast<std::int32_t>(work_.pairs.near);
  work_.pairs.row_far[work_.step.halo_end] = static_cast<std::int32_t>(work_.pairs.far);
  work_.pairs.count = work_.pairs.near + work_.pairs.far;
  // Bonds stretched beyond the interaction radius (possible only when delta_max > R - L) are
  // applied on their own; the other end joins the step if it is not in it yet.
  // A live bond is at most L + delta_max long at the start of a step (longer ones broke at the
  // end of the last one), so when every bond's L + delta_max is inside R there are none.
  work_.loose.count = 0;
  for (std::size_t k = 0; k < (model_.bonds.loose_possible ? work_.step.awake_end : 0); ++k) {
    const std::int32_t i = work_.step.global[k];
    for (std::int32_t a = model_.bonds.adj_start[i]; a < model_.bonds.adj_start[i + 1]; ++a) {
      const std::int32_t b = model_.bonds.adj[a];
      if (!state_.bond_alive[b] || work_.loose.in_pair[b]) continue;
      const std::int32_t j = model_.bonds.ij[2 * b] == i ? model_.bonds.ij[2 * b + 1] : model_.bonds.ij[2 * b];
      std::int32_t lj = work_.step.local[j];
      if (lj >= 0 && lj < static_cast<std::int32_t>(k)) continue;  // awake, counted from j
      if (lj < 0) {
        lj = static_cast<std::int32_t>(work_.step.outer_end++);
        work_.step.local[j] = lj;
        work_.step.global[lj] = j;
      }
      // Oriented as the bond is (i -> j in bond order), like a pair.
      const bool forward = model_.bonds.ij[2 * b] == i;
      work_.loose.bond[work_.loose.count] = b;
      work_.loose.ij[2 * work_.loose.count] = forward ? static_cast<std::int32_t>(k) : lj;
      work_.loose.ij[2 * work_.loose.count + 1] = forward ? lj : static_cast<std::int32_t>(k);
      ++work_.loose.count;
    }
  }
  if (model_.bonds.loose_possible) {
    for (std::size_t p = 0; p < work_.pairs.near; ++p)
      if (work_.pairs.bond[p] >= 0) work_.loose.in_pair[work_.pairs.bond[p]] = 0;
    for (std::size_t p = cap - work_.pairs.far; p < cap; ++p)
      if (work_.pairs.bond[p] >= 0) work_.loose.in_pair[work_.pairs.bond[p]] = 0;
  }
  work_.step.frozen_moving = false;
  for (std::size_t k = work_.step.awake_end; k < work_.step.outer_end; ++k) work_.step.frozen_moving = work_.step.frozen_moving || model_.fixed[work_.step.global[k]];
}

// Walls: for each particle of the step near a collider, the no-slip coupling, the density and
// second moment of the lattice sites inside the solid, and the contact constraint. A collider
// whose bounding box is farther than any of these reach is skipped (its surface is at least
// that far), unless culling is switched off.
void Nucleus::setup_walls(double dt, std::span<const Collider> moving) {
  work_.walls.hit_count = 0;
  work_.walls.particles = 0;
  work_.contacts.particles = 0;
  // A lattice site within R of the particle can be inside the solid only if d < R + h/2.
  const double wall_range = model_.radius + 0.5 * model_.h;
  const std::size_t n_static = model_.statics.size();
  const std::size_t n_coll = n_static + moving.size();
  // Bounding boxes and speed bounds of the colliders.
  std::array<Vec3, 32> lo, hi;
  std::array<bool, 32> bounded;
  for (std::size_t c = 0; c < n_coll; ++c) {
    const Collider& col = c < n_static ? model_.statics[c] : moving[c - n_static];
    bounded[c] = model_.solver.contact_culling && collider_bounds(col, &lo[c], &hi[c]);
  }
  for (std::size_t k = 0; k < work_.step.halo_end; ++k) {
    work_.sys.density[k] = 0.0;
    work_.sys.second_moment[k] = 0.0;
    work_.walls.slot[k] = -1;
  }
  for (std::size_t k = 0; k < work_.step.awake_end; ++k) {
    work_.contacts.slot[k] = -1;
    work_.cull.near_colliders[k] = 0;
    work_.cull.all_colliders[k] = model_.solver.contact_culling ? 0 : 1;
  }
  // Static colliders per particle. A static collider whose lower distance bound (box gap, or
  // the exact distance of a half-space) was at least wall_range + margin where the mask was
  // found is at least wall_range away while the particle stays within the margin of that
  // place (distances are 1-Lipschitz); when also the contact reach bound is inside the wall
  // range (|v| dt <= wall_range - contact - 0.1 h), the test below would skip it, so it is
  // left out without evaluating anything (bit-identical).
  const double mask_margin = kStaticMaskMargin * model_.h;
  const double mask_margin2 = mask_margin * mask_margin;
  const double mask_far = wall_range * (1.0 + 1e-9) + 1e-6 * model_.h + mask_margin;
  const double slow_reach = wall_range - model_.contact - 0.1 * model_.h;
  const double slow_v2 = slow_reach > 0.0 ? (slow_reach / dt) * (slow_reach / dt) : -1.0;
  const std::uint32_t all_statics =
      n_static >= 32 ? ~0u : ((1u << n_static) - 1u);
  const std::uint32_t moving_bits = (n_coll >= 32 ? ~0u : ((1u << n_coll) - 1u)) & ~all_statics;
  for (std::size_t k = 0; k < work_.step.halo_end; ++k) {
    const std::int32_t i = work_.step.global[k];
    const bool awake = k < work_.step.awake_end;
    const Vec3 xi = state_.x[i];
    const Vec3 vi = state_.v[i];
    const double vi_norm = vi.norm();
    std::uint32_t statics_mask = all_statics;
    if (model_.solver.contact_culling && vi.squaredNorm() <= slow_v2 * (1.0 - 1e-9)) {
      if (!((xi - work_.cull.static_ref[i]).squaredNorm() <= mask_margin2)) {
        std::uint32_t mask = 0;
        for (std::size_t kc = 0; kc < n_static; ++kc) {
          const Collider& c = model_.statics[kc];
          double gap = 0.0;  // lower bound of the distance to the solid
          if (bounded[kc]) gap = box_gap(xi, lo[kc], hi[kc]);
          else if (c.kind == ColliderKind::kHalfSpace)
            gap = signed_distance_local(c, to_local(c.pose, work_.frames.identity[kc] != 0, xi), nullptr);
          if (!(gap >= mask_far)) mask |= 1u << kc;
        }
        work_.cull.static_mask[i] = mask;
        work_.cull.static_ref[i] = xi;
      }
      statics_mask = work_.cull.static_mask[i];
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
      const Collider& c = kc < n_static ? model_.statics[kc] : moving[kc - n_static];
      if (bounded[kc]) {
        // The surface is at least box_gap away; the contact reach is at most
        // contact + 0.1 h + |v_i - v_wall| dt. (Compared squared: the bound has a 1e-9 margin,
        // and a collider kept by rounding is skipped by the exact test below.)
        const double v_wall =
            kc < n_static ? 0.0
                          : work_.frames.lin_speed[kc] +
                                (work_.frames.ang_speed[kc] != 0.0
                                     ? work_.frames.ang_speed[kc] * (xi - c.pose.position).norm()
                                     : 0.0);
        const double reach_bound = model_.contact + 0.1 * model_.h + (vi_norm + v_wall) * dt;
        const double bound = std::max(wall_range, reach_bound) * (1.0 + 1e-9);
        if (box_gap2(xi, lo[kc], hi[kc]) >= bound * bound) continue;
      }
      Vec3 normal;
      const bool unrotated = work_.frames.identity[kc] != 0;
      const double d = signed_distance_local(c, to_local(c.pose, unrotated, xi), &normal);
      if (!unrotated) normal = c.pose.orientation * normal;
      const Vec3 vw = kc < n_static ? Vec3::Zero() : c.velocity_at(xi);
      const double vn_rel = (vi - vw).dot(normal);
      const double reach = model_.contact + 0.1 * model_.h + std::max(0.0, -vn_rel) * dt;
      if (d >= wall_range && d >= reach) continue;
      if (hits >= kMaxWallHitsPerParticle || work_.walls.hit_count >= work_.walls.hits.size()) {
        if (awake) work_.cull.all_colliders[k] = 1;  // not tracked: the projection checks everything
        continue;
      }
      ++hits;
      if (awake) work_.cull.near_colliders[k] |= 1u << kc;
      WallHit& w = work_.walls.hits[work_.walls.hit_count++];
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
        const WallTableEntry e = model_.wall_table.at(d);
        work_.sys.density[k] += e.n;
        work_.sys.second_moment[k] += e.s2;
        w.grad = e.grad * normal;
        w.visc = e.visc_t * Eigen::Matrix3d::Identity();
        w.visc(face_axis, face_axis) = e.visc_n;
      } else if (d < wall_range) {
        // The sums depend on where the particle is relative to the solid only (cached; read
        // in place, not copied).
        SiteSums uncached;
        const SiteSums& sums =
            model_.solver.wall_sum_cache
                ? cached_site_sums(static_cast<std::int32_t>(kc), c, i, xi, d)
                : (uncached = site_sums(c, static_cast<std::int32_t>(kc), xi,
                                        to_local(c.pose, unrotated, xi), d));
        work_.sys.density[k] += sums.n;
        work_.sys.second_moment[k] += sums.s2;
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
      if (awake && d < reach && vn_rel <= 1e-12 && (d < model_.contact || !state_.release[i]) && nc < 3) {
        const double approach = d > model_.contact ? -(d - model_.contact) / dt : 0.0;
        cn[nc] = normal;
        ct[nc] = vw.dot(normal) + std::max(approach, std::min(vn_rel, 0.0));
        ++nc;
        w.contact = true;
      }
    }
    if (hits > 0) {
      const std::size_t slot = work_.walls.particles++;
      work_.walls.slot[k] = static_cast<std::int32_t>(slot);
      work_.walls.particle[slot] = static_cast<std::int32_t>(k);
      work_.walls.g[slot] = grad_sum;
      work_.walls.c[slot] = Eigen::Matrix3d::Zero();
    }
    if (!awake) continue;
    state_.release[i] = 0;
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
      const std::size_t slot = work_.contacts.particles++;
      work_.contacts.slot[k] = static_cast<std::int32_t>(slot);
      work_.contacts.particle[slot] = static_cast<std::int32_t>(k);
      work_.contacts.count[slot] = static_cast<std::uint8_t>(ne);
      for (int a = 0; a < ne; ++a) work_.contacts.e[slot][a] = e[a];
      work_.contacts.v[slot] = vc;
    }
  }
}

// Wall sums of collider `kc`'s lattice sites around a particle at x (local: x in the
// collider's frame), d from its surface: each site within R counts with its occupancy (see
// setup_walls). The sites are placed in the collider's frame with the offsets rotated once per
// step (collider_frames), and a box's sites farther than h/2 outside its faces along any local
// axis are rejected before the distance (their occupancy is 0): a particle beside the moving
// blade recomputes these sums nearly every step, and most of its sites are outside the blade.
SiteSums Nucleus::site_sums(const Collider& c, std::int32_t kc, const Vec3& x,
                                     const Vec3& local, double d) const {
  SiteSums sums;
  const double inv_d_eff = 1.0 / std::max(d, 0.25 * model_.h);
  const double inv_n0 = 1.0 / model_.n0;
  const double half = 0.5 * model_.h;
  const bool identity = work_.frames.identity[kc] != 0;
  const Vec3* offsets = identity ? model_.sites.offset.data() : &work_.frames.site_local[kc * model_.sites.offset.size()];
  const bool box = c.kind == ColliderKind::kBox;
  const Vec3 reject = c.half_extents_m + Vec3::Constant(half);
  Vec3 grad_local = Vec3::Zero();
  for (std::size_t o = 0; o < model_.sites.offset.size(); ++o) {
    // sd(site) >= d - |offset|: a site that far cannot be occupied.
    if (d - model_.sites.len[o] >= half) continue;
    // An unrotated collider: the site's local point exactly as signed_distance() forms it.
    const Vec3 p = identity ? Vec3((x + model_.sites.offset[o]) - c.pose.position)
                            : Vec3(local + offsets[o]);
    if (box && (p.x() >= reject.x() || -p.x() >= reject.x() || p.y() >= reject.y() ||
                -p.y() >= reject.y() || p.z() >= reject.z() || -p.z() >= reject.z()))
      continue;  // sd >= |p_a| - b_a >= h/2 on that axis
    Vec3 nq;
    const double sd = signed_distance_local(c, p, &nq);
    double slope = 0.0;
    const double occ = occupancy(sd, model_.h, &slope);
    if (occ <= 0.0) continue;
    sums.n += occ * model_.sites.w[o];
    sums.s2 += occ * model_.sites.wv[o] * model_.sites.r2[o];
    grad_local += (slope * model_.sites.w[o] * inv_n0) * nq;
    sums.visc += (occ * model_.sites.wv[o] * (1.0 + std::max(0.0, -sd) * inv_d_eff)) * model_.sites.uu[o];
  }
  sums.grad = identity ? grad_local : Vec3(c.pose.orientation * grad_local);
  return sums;
}

// Per collider of this step (statics, then moving): its linear and angular speed, whether its
// orientation is the identity, and otherwise the lattice site offsets in its frame.
void Nucleus::collider_frames(std::span<const Collider> moving) {
  const std::size_t n_static = model_.statics.size();
  const std::size_t sites = model_.sites.offset.size();
  for (std::size_t kc = 0; kc < n_static + moving.size(); ++kc) {
    const Collider& c = kc < n_static ? model_.statics[kc] : moving[kc - n_static];
    work_.frames.lin_speed[kc] = c.linear_velocity_m_s.norm();
    work_.frames.ang_speed[kc] = c.angular_velocity_rad_s.norm();
    const Quat& q = c.pose.orientation;
    const bool identity = q.w() == 1.0 && q.x() == 0.0 && q.y() == 0.0 && q.z() == 0.0;
    work_.frames.identity[kc] = identity ? 1 : 0;
    if (identity) continue;
    const Eigen::Matrix3d to_local = q.conjugate().toRotationMatrix();
    for (std::size_t o = 0; o < sites; ++o) work_.frames.site_local[kc * sites + o] = to_local * model_.sites.offset[o];
  }
}

// site_sums of collider `kc` (index over statics then moving) for particle i at x, from the
// cache while i's position in the collider's frame has moved less than the tolerance and the
// collider has turned less than the tolerance over R since they were computed: the sums are
// a function of that relative placement only (a translated collider carries its sums along;
// the lattice of sites is world-aligned, hence the turn limit).
const SiteSums& Nucleus::cached_site_sums(std::int32_t kc, const Collider& c,
                                                   std::int32_t i, const Vec3& x, double d) {
  const double tol = model_.solver.wall_sum_cache_tolerance * model_.h;
  const Vec3 local = to_local(c.pose, work_.frames.identity[kc] != 0, x);
  SiteSums* entries = &work_.site_cache.entries[kMaxWallHitsPerParticle * static_cast<std::size_t>(i)];
  SiteSums* slot = nullptr;
  for (int e = 0; e < kMaxWallHitsPerParticle; ++e) {
    if (entries[e].collider == kc) slot = &entries[e];
  }
  if (slot) {
    const bool placed = (local - slot->local).squaredNorm() < tol * tol;
    const bool turned = !(std::abs(c.pose.orientation.dot(slot->orientation)) > model_.cache_turn_cos);
    if (placed && !turned) return *slot;
  } else {
    slot = &entries[work_.site_cache.next[i]];  // round robin over the particle's entries
    work_.site_cache.next[i] = static_cast<std::uint8_t>((work_.site_cache.next[i] + 1) % kMaxWallHitsPerParticle);
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
    if (std::abs(local[k]) > c.half_extents_m[k] - model_.radius) return false;
  }
  return 2.0 * c.half_extents_m[a] >= model_.radius - d;
}

// Wall sums of a flat face normal to +z at distance d, sampled over [-h/2, R + h/2].
void Nucleus::build_wall_table() {
  const int samples = static_cast<int>(model_.wall_table.entries.size());
  const double lo = -0.5 * model_.h, hi = model_.radius + 0.5 * model_.h;
  model_.wall_table.step = (hi - lo) / (samples - 1);
  model_.wall_table.lo = lo;
  for (int k = 0; k < samples; ++k) {
    const double d = lo + k * model_.wall_table.step;
    const double d_eff = std::max(d, 0.25 * model_.h);
    WallTableEntry e{};
    for (std::size_t o = 0; o < model_.sites.offset.size(); ++o) {
      const double sd = d + model_.sites.offset[o].z();
      double slope = 0.0;
      const double occ = occupancy(sd, model_.h, &slope);
      if (occ <= 0.0) continue;
      const Vec3 u = model_.sites.offset[o] / model_.sites.len[o];
      const double vw = occ * model_.sites.wv[o] * (1.0 + std::max(0.0, -sd) / d_eff);
      e.n += occ * model_.sites.w[o];
      e.s2 += occ * model_.sites.wv[o] * model_.sites.r2[o];
      e.grad += slope * model_.sites.w[o] / model_.n0;
      e.visc_n += vw * u.z() * u.z();
      e.visc_t += vw * u.x() * u.x();
    }
    model_.wall_table.entries[k] = e;
  }
}


namespace {

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
  const double R = model_.radius;
  const double Rd = model_.density_radius;
  const std::size_t cap = work_.pairs.cap;
  const std::size_t far_begin = cap - work_.pairs.far;
  const std::size_t far_awake_begin = cap - work_.pairs.far_awake;
  for (std::size_t k = work_.step.halo_end; k < work_.step.outer_end; ++k) {
    work_.sys.density[k] = 0.0;  // outer particles: partial sums, never read
    work_.sys.second_moment[k] = 0.0;
  }
  // Neighbour sums: density (kernel units) and second moment, the kernels' q from the
  // reciprocal radii (every near pair is inside both radii).
  const double inv_R = 1.0 / R, inv_Rd = 1.0 / Rd;
  const double slope_scale = -3.0 * inv_Rd / model_.n0;  // dw/dr / n0 = slope_scale q^2
  // Row by row (every pair of row k has k as its first end), the first end's sums in
  // registers.
  const std::int32_t* pj = work_.pairs.j.data();
  const double* pr = work_.pairs.r.data();
  for (std::size_t k = 0; k < work_.step.halo_end; ++k) {
    double dk = 1.0;  // self
    double mk = 0.0;
    for (std::int32_t p = work_.pairs.row_near[k]; p < work_.pairs.row_near[k + 1]; ++p) {
      const std::int32_t j = pj[p];
      const double r = pr[p];
      const double qd = std::max(0.0, 1.0 - r * inv_Rd);
      const double w = kernel_of(qd);
      const double wv = viscous_weight_of(std::max(0.0, 1.0 - r * inv_R));
      const double m2 = wv * r * r;
      dk += w;
      work_.sys.density[j] += w;
      work_.pairs.g[p] = slope_scale * qd * qd;
      mk += m2;
      work_.sys.second_moment[j] += m2;
      work_.pairs.wv[p] = wv;
    }
    for (std::size_t p = cap - work_.pairs.row_far[k + 1]; p < cap - work_.pairs.row_far[k]; ++p) {
      const std::int32_t j = pj[p];
      const double r = pr[p];
      const double wv = viscous_weight_of(std::max(0.0, 1.0 - r * inv_R));
      const double m2 = wv * r * r;
      mk += m2;
      work_.sys.second_moment[j] += m2;
      work_.pairs.wv[p] = wv;
    }
    work_.sys.density[k] += dk;
    work_.sys.second_moment[k] += mk;
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
  for (std::size_t k = 0; k < work_.step.halo_end; ++k) {
    const std::int32_t i = work_.step.global[k];
    work_.sys.visc_coef[k] =
        2.0 * model_.mu[i] * model_.volume * model_.s0 / (model_.t0 * std::max(work_.sys.second_moment[k], 0.6 * model_.s0));
    work_.sys.constraint[k] = work_.sys.density[k] / model_.n0 - 1.0;
    work_.sys.press_coef[k] = work_.sys.constraint[k] > -0.01 ? dt * dt * model_.kappa[i] * model_.volume : 0.0;
  }
  for (std::size_t k = work_.step.halo_end; k < work_.step.outer_end; ++k) {
    work_.sys.constraint[k] = 0.0;
    work_.sys.press_coef[k] = 0.0;
    work_.sys.visc_coef[k] = 0.0;
  }
  // Right-hand side: forces at the start of the step (as dt * f) and M v0; rows beyond the
  // awake particles are scratch. Walls: the no-slip tensor, the wall pressure, the no-slip
  // drag toward a moving wall, and the density change the wall's own motion causes
  // (s_i = press_coef * sum_w grad . v_w, scattered through grad C below).
  for (std::size_t k = 0; k < work_.step.outer_end; ++k) {
    const std::int32_t i = work_.step.global[k];
    work_.sys.rhs[k] = dt * (model_.mass[i] * model_.gravity + state_.f_ext[i]);
  }
  for (std::size_t k = 0; k < work_.step.awake_end; ++k) {
    work_.sys.mass[k] = model_.mass[work_.step.global[k]];
    work_.sys.rhs[k] += work_.sys.mass[k] * state_.v[work_.step.global[k]];
  }
  for (std::size_t k = 0; k < work_.step.halo_end; ++k) work_.sys.div[k] = 0.0;
  for (std::size_t w = 0; w < work_.walls.hit_count; ++w) {
    const WallHit& hit = work_.walls.hits[w];
    const std::int32_t k = hit.particle;
    work_.walls.c[work_.walls.slot[k]] += (dt * work_.sys.visc_coef[k]) * hit.visc;
    work_.sys.rhs[k] += (dt * work_.sys.visc_coef[k]) * (hit.visc * hit.v_wall);
    work_.sys.div[k] += hit.grad.dot(hit.v_wall);
  }
  for (std::size_t k = 0; k < work_.step.halo_end; ++k) work_.sys.div[k] *= work_.sys.press_coef[k];
  for (std::size_t w = 0; w < work_.walls.particles; ++w) {
    const std::int32_t k = work_.walls.particle[w];
    work_.sys.rhs[k] -= dt * model_.kappa[work_.step.global[k]] * model_.volume * std::max(work_.sys.constraint[k], 0.0) * work_.walls.g[w];
    work_.sys.rhs[k] += work_.sys.div[k] * work_.walls.g[w];
  }
  // Block-Jacobi preconditioner: the 3x3 diagonal blocks of the system matrix (awake rows).
  // grad_i C_i = -sum_j g_ij n_ij + wall_g_i, accumulated in work_.pcg.q as scratch.
  for (std::size_t k = 0; k < work_.step.halo_end; ++k) {
    const double m = k < work_.step.awake_end ? work_.sys.mass[k] : 1.0;
    work_.sys.diag_inv[k] = {m, m, m, 0.0, 0.0, 0.0};
    work_.pcg.q[k] = Vec3::Zero();
  }
  for (std::size_t w = 0; w < work_.walls.particles; ++w) {
    const std::int32_t k = work_.walls.particle[w];
    const Eigen::Matrix3d& C = work_.walls.c[w];
    Sym3& d = work_.sys.diag_inv[k];
    d[0] += C(0, 0);
    d[1] += C(1, 1);
    d[2] += C(2, 2);
    d[3] += 0.5 * (C(0, 1) + C(1, 0));
    d[4] += 0.5 * (C(0, 2) + C(2, 0));
    d[5] += 0.5 * (C(1, 2) + C(2, 1));
    work_.pcg.q[k] = work_.walls.g[w];
  }
  // Pairs with an awake particle: the implicit coefficient dt c_ij (+ dt^2 k of its bond),
  // the bond force k (r - L) along the pair, the pressure force, the wall-motion term, the
  // diagonal blocks, and the solver's record. The solver's copy is single precision: the
  // iterations stream it, so its size sets their speed; rounding perturbs the operator by
  // ~1e-7 relative (far below the solve tolerance) and symmetrically (both ends of a pair read
  // the same record), so it stays symmetric positive definite.
  // Per particle of the step: the pressure force factor dt kappa V max(C, 0) and half the
  // viscous coefficient times dt (zero beyond the halo).
  double* pf = work_.sys.press_force.data();
  double* hv = work_.sys.half_visc.data();
  for (std::size_t k = 0; k < work_.step.outer_end; ++k) {
    pf[k] = dt * model_.kappa[work_.step.global[k]] * model_.volume * std::max(work_.sys.constraint[k], 0.0);
    hv[k] = 0.5 * dt * work_.sys.visc_coef[k];
  }
  const double* pc = work_.sys.press_coef.data();
  const double dt2 = dt * dt;
  // Row by row over the awake particles (their rows hold exactly the pairs with an awake
  // particle), the first end's sums in registers.
  for (std::size_t k = 0; k < work_.step.halo_end; ++k) pf[k] -= work_.sys.div[k];  // pressure force less wall motion
  // The arrays as local pointers: the scattered stores below could alias the vectors' own
  // members, so the compiler would otherwise reload every base pointer for every pair.
  const Vec3* pn = work_.pairs.n.data();
  const double* pa = work_.pairs.wv.data();
  const double* pg = work_.pairs.g.data();
  const std::int32_t* pb = work_.pairs.bond.data();
  const double* bk = model_.bonds.k.data();
  const double* brest = model_.bonds.rest.data();
  Vec3* rhs = work_.sys.rhs.data();
  Vec3* qv = work_.pcg.q.data();
  Sym3* diag = work_.sys.diag_inv.data();
  PairKernel* kern = work_.pairs.kernel.data();
  const std::int32_t* rnear = work_.pairs.row_near.data();
  const std::int32_t* rfar = work_.pairs.row_far.data();
  for (std::size_t i = 0; i < work_.step.awake_end; ++i) {
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
  if (work_.step.frozen_moving) {
    for (std::size_t p = work_.pairs.near_awake; p < work_.pairs.near; ++p)
      work_.pairs.kernel[p] = {static_cast<float>(work_.pairs.n[p].x()), static_cast<float>(work_.pairs.n[p].y()),
                    static_cast<float>(work_.pairs.n[p].z()), static_cast<float>(work_.pairs.g[p]),
                    work_.pairs.j[p], 0.0f};
    for (std::size_t p = far_begin; p < far_awake_begin; ++p)
      work_.pairs.kernel[p] = {0.0f, 0.0f, 0.0f, 0.0f, work_.pairs.j[p], 0.0f};
  }
  // Loose bonds cache their direction and implicit coefficient dt^2 k for the solver.
  for (std::size_t k = 0; k < work_.loose.count; ++k) {
    const std::int32_t b = work_.loose.bond[k];
    work_.loose.a[k] = 0.0;
    const std::int32_t li = work_.loose.ij[2 * k], lj = work_.loose.ij[2 * k + 1];
    const Vec3 d = min_image(model_, state_.x[work_.step.global[lj]] - state_.x[work_.step.global[li]]);
    const double r = d.norm();
    if (r <= 0.0) continue;
    work_.loose.n[k] = d / r;
    work_.loose.a[k] = dt * dt * model_.bonds.k[b];
    const Vec3 f = dt * model_.bonds.k[b] * (r - model_.bonds.rest[b]) * work_.loose.n[k];
    work_.sys.rhs[li] += f;
    work_.sys.rhs[lj] -= f;
    add_outer(work_.sys.diag_inv[li], work_.loose.a[k], work_.loose.n[k]);
    add_outer(work_.sys.diag_inv[lj], work_.loose.a[k], work_.loose.n[k]);
  }
  for (std::size_t k = 0; k < work_.step.awake_end; ++k) {
    add_outer(work_.sys.diag_inv[k], work_.sys.press_coef[k], work_.pcg.q[k]);
    work_.sys.diag_inv[k] = inverse(work_.sys.diag_inv[k]);
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
  const std::size_t rows = full ? work_.step.halo_end : work_.step.awake_end;   // rows whose pairs are applied
  const std::size_t span = full ? work_.step.outer_end : work_.step.halo_end;   // particles those pairs reach
  const std::size_t cap = work_.pairs.cap;
  F4* xf = work_.apply.x.data();
  F4* yf = work_.apply.y.data();
  float* s = work_.apply.s.data();
  const double* m = work_.sys.mass.data();
  // Per particle, in one pass: the single-precision input, the mass and wall terms in y, and
  // the wall part of the divergence (work_.walls.slot is set on [0, nh)).
  const std::int32_t* slot = work_.walls.slot.data();
  const std::size_t walled = std::min(span, work_.step.halo_end);
  auto init = [&](std::size_t k) {
    xf[k] = F4{static_cast<float>(x[k].x()), static_cast<float>(x[k].y()),
               static_cast<float>(x[k].z()), 0.0f};
    yf[k] = F4{0.0f, 0.0f, 0.0f, 0.0f};
    s[k] = 0.0f;
    if (k < walled && slot[k] >= 0) {
      const std::int32_t w = slot[k];
      y[k] += work_.walls.c[w] * x[k];
      s[k] = static_cast<float>(work_.walls.g[w].dot(x[k]));
    }
  };
  for (std::size_t k = 0; k < work_.step.awake_end; ++k) {
    y[k] = m[k] * x[k];
    init(k);
  }
  for (std::size_t k = work_.step.awake_end; k < span; ++k) {
    y[k] = Vec3::Zero();
    init(k);
  }
  // Loose bonds: dt^2 k n n^T on the relative velocity (pair bonds are in the pair term).
  for (std::size_t k = 0; k < work_.loose.count; ++k) {
    const std::int32_t i = work_.loose.ij[2 * k], j = work_.loose.ij[2 * k + 1];
    const Vec3& nn = work_.loose.n[k];
    const Vec3 f = work_.loose.a[k] * nn.dot(x[j] - x[i]) * nn;
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
  const PairKernel* kr = work_.pairs.kernel.data();
  const std::int32_t* rn = work_.pairs.row_near.data();
  const std::int32_t* rf = work_.pairs.row_far.data();
  float* dnp = work_.apply.dn.data();
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
  const double* pc = work_.sys.press_coef.data();
  for (std::size_t k = 0; k < span; ++k) {
    s[k] = static_cast<float>(s[k] * pc[k]);
    if (k < walled && slot[k] >= 0) y[k] += static_cast<double>(s[k]) * work_.walls.g[slot[k]];
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
  const std::size_t na = work_.step.awake_end;
  Vec3* v = work_.pcg.v.data();
  Vec3* r = work_.pcg.r.data();
  Vec3* z = work_.pcg.z.data();
  Vec3* p = work_.pcg.p.data();
  Vec3* q = work_.pcg.q.data();
  auto filter = [&](Vec3* u) {
    for (std::size_t c = 0; c < work_.contacts.particles; ++c) {
      const std::int32_t k = work_.contacts.particle[c];
      for (int a = 0; a < work_.contacts.count[c]; ++a) u[k] -= work_.contacts.e[c][a] * work_.contacts.e[c][a].dot(u[k]);
    }
  };
  // Initial guess: previous velocity with its constrained components replaced; frozen
  // particles hold still (fixed ones move at their prescribed velocity).
  for (std::size_t k = 0; k < na; ++k) v[k] = state_.v[work_.step.global[k]];
  for (std::size_t c = 0; c < work_.contacts.particles; ++c) {
    const std::int32_t k = work_.contacts.particle[c];
    Vec3 u = v[k];
    for (int a = 0; a < work_.contacts.count[c]; ++a) u -= work_.contacts.e[c][a] * work_.contacts.e[c][a].dot(u);
    v[k] = u + work_.contacts.v[c];
  }
  for (std::size_t k = na; k < work_.step.outer_end; ++k) {
    const std::int32_t i = work_.step.global[k];
    v[k] = model_.fixed[i] ? state_.fixed_v[i] : Vec3::Zero();
  }
  for (const std::int32_t i : model_.fixed_list) state_.v[i] = state_.fixed_v[i];
  apply(v, q, work_.step.frozen_moving);
  // A v on the constrained rows, kept along with v (A v0 + sum alpha A p): the contact forces
  // are its constrained part (reactions_and_pressure), which the filtered residual drops.
  for (std::size_t c = 0; c < work_.contacts.particles; ++c) work_.contacts.av[c] = q[work_.contacts.particle[c]];
  double b_norm2 = 0.0, g_norm2 = 0.0;
  const double g2 = model_.gravity.squaredNorm();
  for (std::size_t k = 0; k < na; ++k) {
    r[k] = work_.sys.rhs[k] - q[k];
    b_norm2 += work_.sys.rhs[k].squaredNorm();
    g_norm2 += work_.sys.mass[k] * work_.sys.mass[k] * g2;
  }
  filter(r);
  // Tolerance relative to the right-hand side, but never below the weight impulse scale: at
  // rest the right-hand side cancels almost exactly and a purely relative test would ask for
  // round-off.
  const double scale = std::sqrt(std::max(b_norm2, g_norm2 * model_.solver.dt_s * model_.solver.dt_s));
  const double tol = model_.solver.tolerance * scale;
  double rz = 0.0;
  double r_norm = 0.0;
  for (std::size_t k = 0; k < na; ++k) z[k] = mul(work_.sys.diag_inv[k], r[k]);
  filter(z);
  for (std::size_t k = 0; k < na; ++k) {
    p[k] = z[k];
    rz += r[k].dot(z[k]);
    r_norm += r[k].squaredNorm();
  }
  // The iterations apply only pairs with an awake particle: p is zero on the halo.
  for (std::size_t k = na; k < work_.step.halo_end; ++k) p[k] = Vec3::Zero();
  r_norm = std::sqrt(r_norm);
  int it = 0;
  const int max_it = std::max(1, model_.solver.max_iterations);
  while (r_norm > tol && it < max_it) {
    apply(p, q, false);
    for (std::size_t c = 0; c < work_.contacts.particles; ++c) work_.contacts.aq[c] = q[work_.contacts.particle[c]];
    filter(q);
    double pq = 0.0;
    for (std::size_t k = 0; k < na; ++k) pq += p[k].dot(q[k]);
    if (!(pq > 0.0)) break;  // converged to round-off (or a non-finite value, caught later)
    const double alpha = rz / pq;
    for (std::size_t c = 0; c < work_.contacts.particles; ++c) work_.contacts.av[c] += alpha * work_.contacts.aq[c];
    double rz_new = 0.0;
    double rn = 0.0;
    // r stays filtered (q is), so r . z equals r . (filtered z): the dot product is taken
    // before the filter.
    for (std::size_t k = 0; k < na; ++k) {
      v[k] += alpha * p[k];
      r[k] -= alpha * q[k];
      rn += r[k].squaredNorm();
      z[k] = mul(work_.sys.diag_inv[k], r[k]);
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
  for (std::size_t k = 0; k < na; ++k) state_.v[work_.step.global[k]] = v[k];
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
  const Vec3* v = work_.pcg.v.data();
  const std::size_t rows = work_.step.frozen_moving ? work_.step.outer_end : work_.step.halo_end;
  // Divergence of the solved velocity (relative to moving walls): C at the end of the step is
  // C + dt * s, and the pressure kappa * that.
  for (std::size_t k = 0; k < rows; ++k) work_.sys.div[k] = 0.0;
  for (std::size_t w = 0; w < work_.walls.particles; ++w) {
    const std::int32_t k = work_.walls.particle[w];
    work_.sys.div[k] = work_.walls.g[w].dot(v[k]);
  }
  for (std::size_t w = 0; w < work_.walls.hit_count; ++w) {
    const WallHit& hit = work_.walls.hits[w];
    work_.sys.div[hit.particle] -= hit.grad.dot(hit.v_wall);
  }
  // Row by row (the near pairs [0, work_.pairs.near_awake) or [0, work_.pairs.near) are rows [0, na) or [0, nh)),
  // the first end's sum in a register: it is complete from the earlier rows when its own row
  // starts, and no later row reaches it, so the additions are the same in the same order.
  {
    const std::size_t near_rows = work_.step.frozen_moving ? work_.step.halo_end : work_.step.awake_end;
    const std::int32_t* rn = work_.pairs.row_near.data();
    const std::int32_t* pj = work_.pairs.j.data();
    const double* pg = work_.pairs.g.data();
    const Vec3* pn = work_.pairs.n.data();
    double* s = work_.sys.div.data();
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
  for (std::size_t k = 0; k < work_.step.halo_end; ++k) {
    const std::int32_t i = work_.step.global[k];
    state_.pressure[i] = work_.sys.press_coef[k] > 0.0
                       ? std::max(0.0, model_.kappa[i] * (work_.sys.constraint[k] + dt * work_.sys.div[k]))
                       : 0.0;
  }
  // Contact forces: the constrained part of A v - b, divided by dt (A v kept by solve()).
  std::size_t w0 = 0;
  while (w0 < work_.walls.hit_count) {
    // The hits of one particle are consecutive.
    const std::int32_t k = work_.walls.hits[w0].particle;
    const std::int32_t i = work_.step.global[k];
    std::size_t end = w0;
    while (end < work_.walls.hit_count && work_.walls.hits[end].particle == k) ++end;
    // Split the constraint force over this particle's contacts: lambda = sum_a a_k n_k.
    double share[kMaxWallHitsPerParticle] = {0, 0, 0, 0};
    const std::int32_t cs = k < static_cast<std::int32_t>(work_.step.awake_end) ? work_.contacts.slot[k] : -1;
    if (cs >= 0) {
      Vec3 lambda = (work_.contacts.av[cs] - work_.sys.rhs[k]) / dt;
      Vec3 constrained = Vec3::Zero();
      for (int a = 0; a < work_.contacts.count[cs]; ++a)
        constrained += work_.contacts.e[cs][a] * work_.contacts.e[cs][a].dot(lambda);
      lambda = constrained;
      int idx[3];
      int nc = 0;
      for (std::size_t h = w0; h < end && nc < 3; ++h)
        if (work_.walls.hits[h].contact) idx[nc++] = static_cast<int>(h - w0);
      if (nc == 1) {
        share[idx[0]] = lambda.dot(work_.walls.hits[w0 + idx[0]].normal);
      } else if (nc > 1) {
        Eigen::Matrix3d G = Eigen::Matrix3d::Identity();
        Vec3 rhs = Vec3::Zero();
        for (int a = 0; a < nc; ++a) {
          rhs[a] = work_.walls.hits[w0 + idx[a]].normal.dot(lambda);
          for (int b = 0; b < nc; ++b)
            G(a, b) = work_.walls.hits[w0 + idx[a]].normal.dot(work_.walls.hits[w0 + idx[b]].normal);
        }
        const Vec3 sol = G.ldlt().solve(rhs);
        for (int a = 0; a < nc; ++a) share[idx[a]] = std::isfinite(sol[a]) ? sol[a] : 0.0;
      }
      // A wall that pulls (negative share) lets go next step.
      for (int a = 0; a < nc; ++a)
        if (share[idx[a]] < 0.0) state_.release[i] = 1;
    }
    for (std::size_t h = w0; h < end; ++h) {
      const WallHit& w = work_.walls.hits[h];
      if (w.collider < 0) continue;
      const Collider& c = moving[w.collider];
      if (c.body < 0 || static_cast<std::size_t>(c.body) >= reactions.size()) continue;
      BodyReaction& r = reactions[c.body];
      // Force on the body = minus the force on the particle.
      Vec3 f = -share[h - w0] * w.normal;                // contact
      const Eigen::Matrix3d C = work_.sys.visc_coef[k] * w.visc;
      f += C * (v[k] - w.v_wall);                        // no-slip drag
      f += model_.volume * state_.pressure[i] * w.grad;              // wall pressure (grad points inward)
      r.force_N += f;
      state_.body_force[i] += f;
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
  for (const std::int32_t i : model_.fixed_list) state_.x[i] += dt * state_.fixed_v[i];
  for (std::size_t k = 0; k < work_.step.awake_end; ++k) {
    const std::int32_t i = work_.step.global[k];
    state_.x[i] += dt * state_.v[i];
  }
  const std::size_t n_static = model_.statics.size();
  const double tiny = 1e-4 * model_.h;
  const double wall_range = model_.radius + 0.5 * model_.h;
  const double free_path = wall_range - model_.contact - 0.01 * model_.h;
  std::size_t hit_cursor = 0;  // work_.walls.hits holds each particle's hits consecutively, by local index
  const std::uint32_t static_bits = n_static >= 32 ? ~0u : ((1u << n_static) - 1u);
  for (std::size_t k = 0; k < work_.step.awake_end; ++k) {
    const std::int32_t i = work_.step.global[k];
    const std::uint32_t near_mask = work_.cull.near_colliders[k];
    const bool check_all = work_.cull.all_colliders[k] != 0;
    while (hit_cursor < work_.walls.hit_count && work_.walls.hits[hit_cursor].particle < static_cast<std::int32_t>(k))
      ++hit_cursor;
    std::size_t hit_end = hit_cursor;
    while (hit_end < work_.walls.hit_count && work_.walls.hits[hit_end].particle == static_cast<std::int32_t>(k))
      ++hit_end;
    double moved = (state_.x[i] - work_.step.x_start[i]).norm();  // kept current as projections move x
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
      const Collider& c = is_static ? model_.statics[c_idx] : moving[c_idx - n_static];
      if (!check_all && !(near_mask & (1u << c_idx))) {
        // Path length in the collider's frame: the particle's displacement plus how far the
        // collider's material near it moved (|v| dt + |w| dt * distance).
        double path = moved;
        if (!is_static)
          path += (work_.frames.lin_speed[c_idx] +
                   work_.frames.ang_speed[c_idx] * (work_.step.x_start[i] - c.pose.position).norm()) *
                  dt * 1.01;
        if (path < free_path) continue;
      }
      const Pose& start = c.pose;
      const Pose& end = is_static ? c.pose : work_.frames.end_pose[c_idx - n_static];
      const bool start_unrotated = work_.frames.identity[c_idx] != 0;
      const bool end_unrotated = is_static ? start_unrotated : work_.frames.end_identity[c_idx - n_static] != 0;
      const Vec3 p0 = to_local(start, start_unrotated, work_.step.x_start[i]);
      Vec3 p1 = to_local(end, end_unrotated, state_.x[i]);
      const double len = (p1 - p0).norm();
      // The start distance is the one setup_walls found for this particle's hit on c (the same
      // evaluation). For an exact distance (1-Lipschitz: not the sampled bone) a path shorter
      // than d0 - contact - 2 tiny can neither end inside nor cross the inflated surface, the
      // test below would pass: skip both distances.
      const std::int32_t hit_id = is_static ? -1 - static_cast<std::int32_t>(c_idx)
                                            : static_cast<std::int32_t>(c_idx - n_static);
      std::size_t h = hit_cursor;
      while (h < hit_end && work_.walls.hits[h].collider != hit_id) ++h;
      const bool known = h < hit_end;
      if (known && c.kind != ColliderKind::kSdfGrid &&
          len <= work_.walls.hits[h].distance - model_.contact - 2.0 * tiny)
        continue;
      Vec3 n1;
      const double d1 = signed_distance_local(c, p1, &n1);
      Vec3 n0;
      const double d0 = known ? work_.walls.hits[h].distance : signed_distance_local(c, p0, &n0);
      // The path cannot reach the inflated surface (triangle inequality on distances).
      if (d1 >= model_.contact - tiny && len <= d0 + d1 - 2.0 * model_.contact) continue;
      Vec3 normal;   // local normal of the face the particle is held on
      Vec3 surface;  // a local point of that face
      bool hit = false;
      if (d0 < model_.contact) {
        // Started in contact: the exit side is the start side.
        if (d1 >= model_.contact - tiny) continue;
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
          const double d = signed_distance_local(c, p0 + t * u, &nn) - model_.contact;
          if (d < tiny) {
            normal = nn;
            surface = p0 + t * u - (d + model_.contact) * nn;
            hit = true;
            break;
          }
          t += d;
        }
        if (!hit) {
          if (d1 >= model_.contact - tiny) continue;
          normal = n1;  // ended inside without a traced entry (grazing): use the end normal
          surface = p1 - d1 * n1;
          hit = true;
        }
      }
      // Put the particle on the entry face's plane at the contact distance, keeping its
      // tangential motion; if that is still inside (a corner), step back to the entry side.
      Vec3 q = p1 + std::max(0.0, model_.contact - (p1 - surface).dot(normal)) * normal;
      Vec3 nq;
      const double dq = signed_distance_local(c, q, &nq);
      if (dq < model_.contact - tiny) {
        if (dq > -model_.contact && nq.dot(normal) > 0.0) q += (model_.contact - dq) * nq;
        else q = surface + model_.contact * normal;
      }
      state_.x[i] = end.apply(q);
      moved = (state_.x[i] - work_.step.x_start[i]).norm();
      projected = true;
      // Remove the approaching normal velocity relative to the surface; its impulse is a
      // force on the collider's body.
      const Vec3 nw = end.orientation * normal;
      const Vec3 vw = is_static ? Vec3::Zero() : moving[c_idx - n_static].velocity_at(state_.x[i]);
      const double vn = (state_.v[i] - vw).dot(nw);
      if (vn < 0.0) {
        state_.v[i] -= vn * nw;
        if (!is_static) {
          const Collider& mc = moving[c_idx - n_static];
          if (mc.body >= 0 && static_cast<std::size_t>(mc.body) < reactions.size()) {
            BodyReaction& r = reactions[mc.body];
            const Vec3 f = model_.mass[i] * vn / dt * nw;  // minus the particle's momentum change rate
            r.force_N += f;
            state_.body_force[i] += f;
            r.torque_Nm += (state_.x[i] - r.reference_point).cross(f);
          }
        }
      }
    }
  }
  // Periodic wrap.
  for (int a = 0; a < 3; ++a) {
    if (!model_.options.periodic[a]) continue;
    const double lo = model_.options.periodic_min_m[a];
    const double L = model_.options.periodic_max_m[a] - lo;
    for (std::size_t k = 0; k < work_.step.awake_end; ++k) {
      const std::int32_t i = work_.step.global[k];
      state_.x[i][a] = lo + (state_.x[i][a] - lo) - L * std::floor((state_.x[i][a] - lo) / L);
    }
  }
}

// Bonds break when their force exceeds k * delta_max, i.e. |stretch| > delta_max
// (seed Eq. 9-10). Only bonds of awake or fixed particles can have changed length.
void Nucleus::break_bonds() {
  auto test = [&](std::int32_t b) {
    if (!state_.bond_alive[b]) return;
    const std::int32_t i = model_.bonds.ij[2 * b], j = model_.bonds.ij[2 * b + 1];
    // |r - L| > delta  <=>  r^2 > (L + delta)^2 or r^2 < (L - delta)^2 (the latter only
    // when L > delta): no square root per bond. An unbreakable bond (delta <= 0) has the
    // bounds +inf and 0, which no r^2 passes, so it needs no test of its own.
    const double r2 = min_image(model_, state_.x[j] - state_.x[i]).squaredNorm();
    if (r2 > model_.bonds.break_hi2[b] || r2 < model_.bonds.break_lo2[b]) {
      state_.bond_alive[b] = 0;
      ++state_.broken_bonds;
      for (const std::int32_t e : {i, j}) {
        if (model_.fixed[e] || state_.wake_next[e]) continue;
        state_.wake_next[e] = 1;
        state_.wake_list[state_.wake_count++] = e;
      }
    }
  };
  // Every live bond of an awake particle is carried by exactly one of this step's pairs with
  // an awake particle (it was shorter than R at the start) or is a loose bond.
  for (std::size_t p = 0; p < work_.pairs.near_awake; ++p)
    if (work_.pairs.bond[p] >= 0) test(work_.pairs.bond[p]);
  for (std::size_t p = work_.pairs.cap - work_.pairs.far_awake; p < work_.pairs.cap; ++p)
    if (work_.pairs.bond[p] >= 0) test(work_.pairs.bond[p]);
  for (std::size_t k = 0; k < work_.loose.count; ++k) test(work_.loose.bond[k]);
  // Fixed particles move too: all their bonds (one shared with an awake particle is tested
  // again, with the same result).
  for (const std::int32_t u : model_.fixed_list)
    for (std::int32_t a = model_.bonds.adj_start[u]; a < model_.bonds.adj_start[u + 1]; ++a) test(model_.bonds.adj[a]);
}

}  // namespace acdr
