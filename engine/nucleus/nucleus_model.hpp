// The nucleus's model: what is fixed once the nucleus is built (configuration copies, lengths
// derived from the spacing, the rest lattice's neighbour sites and the flat-wall table built
// from them, the bond table, the particles' constants and the static colliders). Every stage
// reads it and none writes it; the caller may change only the gravity between steps
// (Nucleus::set_gravity). Sizes: N particles, B bonds, S lattice sites within R.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/core/types.hpp"
#include "engine/geometry/collider.hpp"
#include "engine/nucleus/nucleus_config.hpp"
#include "engine/nucleus/nucleus_options.hpp"

namespace acdr {

/// The neighbour sites of a lattice point within the interaction radius R (the full rest
/// lattice, S of each): walls count the sites inside a solid as neighbours.
struct LatticeSites {
  std::vector<Vec3> offset;            // S, m
  std::vector<double> w;               // S, density kernel weight
  std::vector<double> r2;              // S, squared length, m^2
  std::vector<double> wv;              // S, viscous weight
  std::vector<double> len;             // S, length, m
  std::vector<Eigen::Matrix3d> uu;     // S, u u^T of the unit direction u
  std::size_t size() const { return offset.size(); }
};

/// Wall sums of one flat face at a distance d (see build_wall_table).
struct WallTableEntry {
  double n = 0.0;       // density share
  double s2 = 0.0;      // second-moment share, m^2
  double grad = 0.0;    // d(density)/dd / n0 along the normal, 1/m
  double visc_n = 0.0;  // no-slip tensor, normal component
  double visc_t = 0.0;  // no-slip tensor, tangential components
};

/// Flat-face wall sums sampled over d in [lo, lo + (size - 1) step], linearly interpolated.
struct WallTable {
  std::array<WallTableEntry, 1024> entries{};
  double lo = 0.0;    // m
  double step = 1.0;  // m

  WallTableEntry at(double d) const {
    const double u = std::clamp((d - lo) / step, 0.0, static_cast<double>(entries.size() - 1));
    const std::size_t k = std::min(static_cast<std::size_t>(u), entries.size() - 2);
    const double f = u - k;
    const WallTableEntry& a = entries[k];
    const WallTableEntry& b = entries[k + 1];
    return {a.n + f * (b.n - a.n), a.s2 + f * (b.s2 - a.s2), a.grad + f * (b.grad - a.grad),
            a.visc_n + f * (b.visc_n - a.visc_n), a.visc_t + f * (b.visc_t - a.visc_t)};
  }
};

/// The bonds as built (B of each); whether one is still intact is state (bond_alive).
struct BondTable {
  std::vector<std::int32_t> ij;         // 2B: particles i, j of each bond
  std::vector<double> rest;             // B, rest length L, m
  std::vector<double> k;                // B, stiffness, N/m
  std::vector<double> break_stretch;    // B, delta_max, m; <= 0 unbreakable
  std::vector<double> break_hi2;        // B, (L + delta)^2, m^2: longer breaks (+inf: never)
  std::vector<double> break_lo2;        // B, (L - delta)^2, m^2: shorter breaks (0: never)
  std::vector<std::int32_t> adj_start;  // N + 1: bonds of each particle (CSR)
  std::vector<std::int32_t> adj;        // 2B bond indices, by particle, in bond order
  bool loose_possible = true;  // some bond can outgrow R (unbreakable, or L + delta >= R)
  std::size_t size() const { return rest.size(); }
  /// The other particle of bond b, seen from particle i.
  std::int32_t other(std::int32_t b, std::int32_t i) const {
    return ij[2 * b] == i ? ij[2 * b + 1] : ij[2 * b];
  }
};

struct NucleusModel {
  NucleusConfig config;    // materials never empty
  SolverConfig solver;
  NucleusOptions options;
  Vec3 gravity = Vec3::Zero();  // m/s^2; the one field the caller may change between steps
  bool periodic = false;        // any periodic axis (min_image is the identity otherwise)
  std::vector<Collider> statics;

  double h = 1e-3;               // spacing, m
  double volume = 1e-9;          // h^3, m^3
  double radius = 1.5e-3;        // interaction radius R, m
  double density_radius = 1.5e-3;  // density kernel support, m
  double contact = 0.5e-3;       // contact distance from surfaces, m
  double skin = 0.0;             // Verlet skin, m
  double n0 = 1.0;   // rest number density sum (kernel units) of the full lattice
  double s0 = 1.0;   // rest weighted second moment sum w r^2 of the full lattice, m^2
  double t0 = 1.0;   // rest weighted fourth moment sum w r_x^2 r_z^2 / r^2, m^2
  double cache_turn_cos = 1.0;   // cos of half the wall-sum cache's turn limit
  double bond_radius = 1.5e-3;   // particles closer than this may bond (build; re-bonding), m
  bool rebonding = false;        // some material re-bonds (MaterialConfig::rebond_time_s > 0)
  bool surface_tension = false;  // some particle's material has a surface tension
  double tension_reach = 1.5e-3;  // the surface tension's reach: min(bond radius, R), m

  LatticeSites sites;
  WallTable wall_table;  // flat-face wall sums over d
  BondTable bonds;

  // ---- Particle constants (N each) ----
  std::vector<double> mass;              // kg
  std::vector<double> mu;                // viscosity, Pa s
  std::vector<double> kappa;             // bulk modulus, Pa
  std::vector<double> tension_force;     // surface tension's peak pair force F_c, N (0: none)
  std::vector<std::uint8_t> material;    // index into config.materials
  std::vector<std::uint8_t> fixed;       // 1 = kinematic (moves at its prescribed velocity)
  std::vector<std::int32_t> fixed_list;  // the fixed particles, ascending

  std::size_t particle_count() const { return mass.size(); }
};

/// The shortest periodic image of a separation d (d itself without periodic axes).
inline Vec3 min_image(const NucleusModel& model, const Vec3& d) {
  if (!model.periodic) return d;
  Vec3 out = d;
  for (int a = 0; a < 3; ++a) {
    if (!model.options.periodic[a]) continue;
    const double L = model.options.periodic_max_m[a] - model.options.periodic_min_m[a];
    out[a] -= L * std::round(out[a] / L);
  }
  return out;
}

}  // namespace acdr
