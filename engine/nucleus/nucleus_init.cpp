// Building a nucleus: the particles and bonds of lattice blocks, the model (rest sums of the
// lattice, site tables, wall table, particle constants, bond table), the initial state, and
// the workspace with every capacity a step needs.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "engine/nucleus/neighbor_grid.hpp"
#include "engine/nucleus/nucleus_math.hpp"
#include "engine/nucleus/nucleus_stages.hpp"
#include "engine/nucleus/surface_tension.hpp"

namespace acdr::nucleus {
namespace {

// Lattice points at min + (i + 1/2) h of each block (a block that fills a box touches its
// walls at h/2), leaving out those inside a static collider.
void add_lattice_particles(const NucleusConfig& config, const NucleusOptions& options,
                           std::span<const Collider> static_colliders,
                           NucleusParticleSetup& setup) {
  const double h = config.spacing_m;
  const double contact = options.contact_radius_factor * h;
  for (const auto& block : config.blocks) {
    Eigen::Vector3i n;
    for (int a = 0; a < 3; ++a)
      n[a] = std::max(1, static_cast<int>(std::lround((block.max_m[a] - block.min_m[a]) / h)));
    for (int k = 0; k < n.z(); ++k)
      for (int j = 0; j < n.y(); ++j)
        for (int i = 0; i < n.x(); ++i) {
          const Vec3 p = block.min_m + h * Vec3(i + 0.5, j + 0.5, k + 0.5);
          if (!block.contains(p)) continue;  // anatomy: cylinder, ring, cutout
          bool inside = false;
          for (const auto& c : static_colliders)
            if (signed_distance(c, p, nullptr) < 0.5 * contact) inside = true;
          if (inside) continue;
          setup.positions_m.push_back(p);
          setup.materials.push_back(static_cast<std::uint8_t>(block.material));
        }
  }
}

// Bonds between lattice neighbours closer than bond_radius_factor * h (brute force over a
// temporary grid; construction only).
void add_lattice_bonds(const NucleusConfig& config, const NucleusOptions& options,
                       NucleusParticleSetup& setup) {
  const std::size_t n = setup.positions_m.size();
  const double bond_r = config.bond_radius_factor * config.spacing_m;
  NeighborGrid grid;
  grid.reserve(n);
  grid.build(setup.positions_m, bond_r, {false, false, false}, Vec3::Zero(), Vec3::Zero());
  std::vector<MaterialConfig> mats = config.materials;
  if (mats.empty()) mats.emplace_back();
  if (!options.bonds_enabled) return;
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

// Rest sums of the full cubic lattice: the normalisations n0 (density) and s0, t0
// (viscosity), and the table of its sites within R.
void build_lattice_sites(NucleusModel& model) {
  const double h = model.h;
  model.n0 = 1.0;
  model.s0 = 0.0;
  model.t0 = 0.0;
  LatticeSites& sites = model.sites;
  sites = LatticeSites{};
  const int m = static_cast<int>(std::ceil(model.options.neighbor_radius_factor));
  for (int a = -m; a <= m; ++a)
    for (int b = -m; b <= m; ++b)
      for (int c = -m; c <= m; ++c) {
        if (a == 0 && b == 0 && c == 0) continue;
        const double r = h * std::sqrt(double(a * a + b * b + c * c));
        if (r >= model.radius) continue;
        const double wv = viscous_weight(r, model.radius);
        model.n0 += kernel(r, model.density_radius);
        model.s0 += wv * r * r;
        model.t0 += wv * (a * h) * (a * h) * (c * h) * (c * h) / (r * r);
        sites.offset.push_back(h * Vec3(a, b, c));
        sites.w.push_back(kernel(r, model.density_radius));
        sites.wv.push_back(wv);
        sites.r2.push_back(r * r);
        sites.len.push_back(r);
        const Vec3 u = h * Vec3(a, b, c) / r;
        sites.uu.push_back(u * u.transpose());
      }
}

// Per particle: material (clamped to the configured ones), mass, viscosity, bulk modulus,
// and which particles are fixed.
void build_particle_constants(NucleusModel& model, const NucleusParticleSetup& setup) {
  const std::size_t n = setup.positions_m.size();
  model.material.assign(n, 0);
  if (setup.materials.size() == n) model.material = setup.materials;
  model.fixed.assign(n, 0);
  if (setup.fixed.size() == n) model.fixed = setup.fixed;
  model.mass.resize(n);
  model.mu.resize(n);
  model.kappa.resize(n);
  model.tension_force.resize(n);
  model.surface_tension = false;
  model.tension_reach = std::min(model.bond_radius, model.radius);
  for (std::size_t i = 0; i < n; ++i) {
    model.material[i] = static_cast<std::uint8_t>(
        std::min<std::size_t>(model.material[i], model.config.materials.size() - 1));
    const MaterialConfig& mat = model.config.materials[model.material[i]];
    model.mass[i] = mat.density_kg_m3 * model.volume;
    model.mu[i] = mat.viscosity_Pa_s;
    model.kappa[i] = mat.bulk_modulus_Pa;
    model.tension_force[i] =
        surface_tension_peak_force(mat.surface_tension_N_m, model.h, model.tension_reach);
    model.surface_tension = model.surface_tension || model.tension_force[i] > 0.0;
  }
  model.fixed_list.clear();
  for (std::size_t i = 0; i < n; ++i)
    if (model.fixed[i]) model.fixed_list.push_back(static_cast<std::int32_t>(i));
}

// The bonds (a rest length < 0 is the initial distance), the squared lengths at which each
// breaks (break_bonds; 0 and +inf when unbreakable), whether any can outgrow R, and the
// bonds of each particle (CSR, in bond order).
void build_bond_table(NucleusModel& model, const NucleusParticleSetup& setup) {
  const std::size_t n = setup.positions_m.size();
  const std::vector<Vec3>& x = setup.positions_m;
  BondTable& bonds = model.bonds;
  const std::size_t nb = setup.bonds.size();
  bonds.ij.resize(2 * nb);
  bonds.rest.resize(nb);
  bonds.k.resize(nb);
  bonds.break_stretch.resize(nb);
  for (std::size_t b = 0; b < nb; ++b) {
    const auto& bond = setup.bonds[b];
    assert(bond.i >= 0 && bond.j >= 0 && std::size_t(bond.i) < n && std::size_t(bond.j) < n);
    bonds.ij[2 * b] = bond.i;
    bonds.ij[2 * b + 1] = bond.j;
    bonds.rest[b] = bond.rest_length_m >= 0.0 ? bond.rest_length_m : (x[bond.j] - x[bond.i]).norm();
    bonds.k[b] = bond.stiffness_N_m;
    bonds.break_stretch[b] = bond.break_stretch_m;
  }
  bonds.break_hi2.assign(nb, std::numeric_limits<double>::infinity());
  bonds.break_lo2.assign(nb, 0.0);
  for (std::size_t b = 0; b < nb; ++b) {
    if (bonds.break_stretch[b] <= 0.0) continue;
    const double hi = bonds.rest[b] + bonds.break_stretch[b];
    const double lo = bonds.rest[b] - bonds.break_stretch[b];
    bonds.break_hi2[b] = hi * hi;
    bonds.break_lo2[b] = lo > 0.0 ? lo * lo : 0.0;
  }
  bonds.loose_possible = false;
  for (std::size_t b = 0; b < nb; ++b)
    if (bonds.break_stretch[b] <= 0.0 || bonds.rest[b] + bonds.break_stretch[b] >= model.radius)
      bonds.loose_possible = true;
  bonds.adj_start.assign(n + 1, 0);
  for (std::size_t b = 0; b < nb; ++b) {
    ++bonds.adj_start[bonds.ij[2 * b] + 1];
    ++bonds.adj_start[bonds.ij[2 * b + 1] + 1];
  }
  for (std::size_t i = 0; i < n; ++i) bonds.adj_start[i + 1] += bonds.adj_start[i];
  bonds.adj.assign(2 * nb, 0);
  std::vector<std::int32_t> cursor(bonds.adj_start.begin(), bonds.adj_start.end() - 1);
  for (std::size_t b = 0; b < nb; ++b) {
    bonds.adj[cursor[bonds.ij[2 * b]]++] = static_cast<std::int32_t>(b);
    bonds.adj[cursor[bonds.ij[2 * b + 1]]++] = static_cast<std::int32_t>(b);
  }
}

}  // namespace

// The Verlet rows: every particle's row once per grid build, with room for 50 % compression.
void reserve_rows(const NucleusModel& model, std::size_t n, VerletRows& rows) {
  std::size_t lattice = 0;  // lattice sites within R + skin
  const double reach = model.options.neighbor_radius_factor + model.options.skin_factor;
  const int mm = static_cast<int>(std::ceil(reach));
  for (int a = -mm; a <= mm; ++a)
    for (int b = -mm; b <= mm; ++b)
      for (int c = -mm; c <= mm; ++c)
        if (a * a + b * b + c * c > 0 && a * a + b * b + c * c < reach * reach) ++lattice;
  rows.grid.reserve(std::max<std::size_t>(n, 1));
  rows.x_built.assign(n, Vec3::Zero());
  rows.grid_valid = false;
  rows.epoch = 0;
  rows.epoch_of.assign(n, 0);
  rows.start.assign(n, 0);
  rows.lower_at.assign(n, 0);
  rows.lower_len.assign(n, 0);
  const std::size_t row_cap = std::max<std::size_t>(64, n * (lattice * 3 / 2 + 8));
  rows.j.assign(row_cap, 0);
  rows.bond.assign(row_cap, -1);
  rows.scratch_j.assign(4 * lattice + 64, 0);
  rows.scratch_bond.assign(4 * lattice + 64, 0);
  rows.scratch_bucket.assign(4 * lattice + 64, 0);
  rows.scratch_r2.assign(4 * lattice + 64, 0.0f);
  rows.upper.assign(n, 0);
  rows.beyond.assign(n, 0);
  rows.r2.assign(row_cap, 0.0f);
  rows.used = 0;
  rows.partner_bond.assign(n, -1);
}

namespace {

void reserve_pairs(const NucleusModel& model, std::size_t n, NucleusWorkspace& work) {
  PairList& pairs = work.pairs;
  pairs.cap =
      std::max<std::size_t>(16, n * std::max<std::size_t>(model.options.max_neighbors, 1) / 2);
  pairs.i.assign(pairs.cap, 0);
  pairs.j.assign(pairs.cap, 0);
  pairs.n.assign(pairs.cap, Vec3::Zero());
  pairs.r.assign(pairs.cap, 0.0);
  pairs.wv.assign(pairs.cap, 0.0);
  pairs.g.assign(pairs.cap, 0.0);
  pairs.bond.assign(pairs.cap, -1);
  pairs.kernel.assign(pairs.cap, PairKernel{0.0f, 0.0f, 0.0f, 0.0f, 0, 0.0f});
  pairs.row_near.assign(n + 1, 0);
  pairs.row_far.assign(n + 1, 0);
  ApplyScratch& scratch = work.apply;
  scratch.dn.assign(pairs.cap, 0.0f);
  scratch.x.assign(n, F4{0.0f, 0.0f, 0.0f, 0.0f});
  scratch.y.assign(n, F4{0.0f, 0.0f, 0.0f, 0.0f});
  scratch.s.assign(n, 0.0f);
  const std::size_t nb = model.bonds.size();
  LooseBonds& loose = work.loose;
  loose.in_pair.assign(nb, 0);
  loose.bond.assign(nb, 0);
  loose.ij.assign(2 * nb, 0);
  loose.n.assign(nb, Vec3::Zero());
  loose.a.assign(nb, 0.0);
}

void reserve_system(std::size_t n, StepSystem& sys, PcgVectors& pcg) {
  sys.second_moment.assign(n, 0.0);
  sys.density.assign(n, 0.0);
  sys.constraint.assign(n, 0.0);
  sys.press_coef.assign(n, 0.0);
  sys.visc_coef.assign(n, 0.0);
  sys.press_force.assign(n, 0.0);
  sys.half_visc.assign(n, 0.0);
  sys.mass.assign(n, 0.0);
  sys.rhs.assign(n, Vec3::Zero());
  sys.diag_inv.assign(n, {1, 1, 1, 0, 0, 0});
  sys.div.assign(n, 0.0);
  pcg.v.assign(n, Vec3::Zero());
  pcg.r.assign(n, Vec3::Zero());
  pcg.z.assign(n, Vec3::Zero());
  pcg.p.assign(n, Vec3::Zero());
  pcg.q.assign(n, Vec3::Zero());
}

void reserve_walls(const NucleusModel& model, std::size_t n, NucleusWorkspace& work) {
  StepWalls& walls = work.walls;
  walls.particle.assign(n, 0);
  walls.c.assign(n, Eigen::Matrix3d::Zero());
  walls.g.assign(n, Vec3::Zero());
  walls.slot.assign(n, -1);
  walls.particles = 0;
  walls.hits.resize(kMaxWallHitsPerParticle * n + 16);
  StepContacts& contacts = work.contacts;
  contacts.particle.assign(n, 0);
  contacts.count.assign(n, 0);
  contacts.e.assign(n, {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()});
  contacts.v.assign(n, Vec3::Zero());
  contacts.slot.assign(n, -1);
  contacts.av.assign(n, Vec3::Zero());
  contacts.aq.assign(n, Vec3::Zero());
  contacts.particles = 0;
  ColliderCulling& cull = work.cull;
  cull.near_colliders.assign(n, 0);
  cull.all_colliders.assign(n, 0);
  cull.static_ref.assign(n, Vec3::Constant(std::numeric_limits<double>::quiet_NaN()));
  cull.static_mask.assign(n, 0);
  work.site_cache.entries.assign(kMaxWallHitsPerParticle * n, SiteSums{});
  work.site_cache.next.assign(n, 0);
  work.frames.site_local.assign(kMaxStepColliders * model.sites.size(), Vec3::Zero());
}

}  // namespace

NucleusParticleSetup lattice_setup(const NucleusConfig& config, const NucleusOptions& options,
                                   std::span<const Collider> static_colliders) {
  NucleusParticleSetup setup;
  add_lattice_particles(config, options, static_colliders, setup);
  add_lattice_bonds(config, options, setup);
  return setup;
}

void build_model(NucleusModel& model, std::span<const Collider> static_colliders,
                 const NucleusParticleSetup& setup) {
  model.h = model.config.spacing_m;
  assert(model.h > 0.0 && "nucleus spacing must be positive");
  model.statics.assign(static_colliders.begin(), static_colliders.end());
  if (model.config.materials.empty()) model.config.materials.emplace_back();
  model.volume = model.h * model.h * model.h;
  model.radius = model.options.neighbor_radius_factor * model.h;
  model.density_radius = std::min(model.options.density_radius_factor * model.h, model.radius);
  model.contact = model.options.contact_radius_factor * model.h;
  model.skin = model.options.skin_factor * model.h;
  model.periodic =
      model.options.periodic[0] || model.options.periodic[1] || model.options.periodic[2];
  model.cache_turn_cos =
      std::cos(0.5 * model.solver.wall_sum_cache_tolerance * model.h / model.radius);
  model.bond_radius = model.config.bond_radius_factor * model.h;
  model.rebonding = false;
  if (model.options.bonds_enabled)
    for (const MaterialConfig& m : model.config.materials)
      model.rebonding = model.rebonding || m.rebond_time_s > 0.0;
  build_lattice_sites(model);
  build_wall_table(model);
  build_particle_constants(model, setup);
  build_bond_table(model, setup);
}

void init_state(const NucleusModel& model, const NucleusParticleSetup& setup,
                NucleusState& state) {
  const std::size_t n = setup.positions_m.size();
  state.x = setup.positions_m;
  state.v.assign(n, Vec3::Zero());
  if (setup.velocities_m_s.size() == n) state.v = setup.velocities_m_s;
  state.f_ext.assign(n, Vec3::Zero());
  state.fixed_v.assign(n, Vec3::Zero());
  state.kinematic = model.fixed;
  state.kinematic_list.reserve(n);
  state.kinematic_list = model.fixed_list;
  state.awake.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) state.awake[i] = model.fixed[i] ? 0 : 1;
  state.active.assign(n, 0);
  state.active_count = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (state.awake[i]) state.active[state.active_count++] = static_cast<std::int32_t>(i);
  state.calm.assign(n, 0);
  state.wake_next.assign(n, 0);
  state.wake_list.assign(n, 0);
  state.wake_count = 0;
  state.bond_alive.assign(model.bonds.size(), 1);
  state.broken_bonds = 0;
  // The re-formed bonds' pool: room for every particle to hold its full share.
  ReformedBonds& reformed = state.reformed;
  reformed = ReformedBonds{};
  if (model.rebonding) {
    const std::size_t per = ReformedBonds::kPerParticle;
    const std::size_t cap = per * n / 2;
    reformed.ij.assign(2 * cap, 0);
    reformed.rest.assign(cap, 0.0);
    reformed.k.assign(cap, 0.0);
    reformed.break_hi2.assign(cap, 0.0);
    reformed.break_lo2.assign(cap, 0.0);
    reformed.alive.assign(cap, 0);
    reformed.free.resize(cap);
    for (std::size_t s = 0; s < cap; ++s)  // slot 0 on top
      reformed.free[s] = static_cast<std::int32_t>(cap - 1 - s);
    reformed.free_count = cap;
    reformed.of.assign(per * n, -1);
    reformed.settled_s.assign(n, 0.0);
  }
  state.pressure.assign(n, 0.0);
  state.body_force.assign(n, Vec3::Zero());
  state.static_force.assign(n, Vec3::Zero());
}

void reserve_workspace(const NucleusModel& model, NucleusWorkspace& work) {
  const std::size_t n = model.particle_count();
  reserve_rows(model, n, work.rows);
  work.step.local.assign(n, -1);
  work.step.global.assign(n, 0);
  work.step.awake_end = work.step.halo_end = work.step.outer_end = 0;
  work.step.x_start.assign(n, Vec3::Zero());
  reserve_pairs(model, n, work);
  reserve_system(n, work.sys, work.pcg);
  reserve_walls(model, n, work);
  work.stamp.assign(n, 0);
  work.separation_rate2.assign(model.rebonding ? n : 0, 0.0);
}

}  // namespace acdr::nucleus
