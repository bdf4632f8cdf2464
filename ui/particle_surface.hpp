// A smooth closed surface over a set of particles, for drawing material as material rather than
// as beads. The surface is the zero level set of the particle-surface field of Zhu & Bridson
// ("Animating sand as a fluid", SIGGRAPH 2005): phi(x) = |x - xbar(x)| - r, where xbar is the
// kernel-weighted mean of the particle centres near x and r the radius a particle stands for.
// A lone particle becomes a sphere of radius r and a flat layer a flat face r beyond its
// centres. Left alone, that field joins any two particles within twice the kernel support by
// a neck; so that the picture never shows scattered particles as one lump, the surface is also
// kept within half the join distance of some particle centre: phi = max(phi_zb, d_nearest -
// join/2). Particles closer than `join_spacings` merge into one smooth piece; farther ones stay
// apart once their gap is wider than about a grid cell (a narrower one falls between samples).
// The field is sampled on a grid that covers only the particles' bounds and extracted with the
// engine's marching tetrahedra (engine/geometry/iso_surface.hpp); normals are the field's
// gradient, so the surface shades smoothly.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace acdr {

struct ParticleSurfaceOptions {
  /// Radius a particle stands for, in lattice spacings (0.62 would keep the volume h^3).
  float radius_spacings = 0.6f;
  /// Support of the kernel w = (1 - d^2/R^2)^3, in spacings: particles closer than about this
  /// are drawn as one piece.
  float support_spacings = 1.8f;
  /// Particles farther apart than this (in spacings, plus about a grid cell) are never drawn
  /// joined. Above the
  /// lattice's largest hole (the cube centre, sqrt(3)/2 spacings from its corners, doubled), so
  /// undisturbed material has no holes; about the range at which the model's particles still
  /// interact (its viscous and pressure kernels reach 1.98 spacings).
  float join_spacings = 1.8f;
  /// Side of a grid cell, in spacings. Half a spacing keeps a lone particle round and the
  /// extraction of a 600-particle nucleus near 6 ms (docs/trainee-view.md).
  float cell_spacings = 0.5f;
  /// Grid points allowed; cells grow when the particles spread wider (material flung far).
  std::size_t max_grid_points = std::size_t{1} << 20;
};

/// Triangles of the surface (counter-clockwise seen from outside) with unit vertex normals.
struct ParticleSurface {
  std::vector<Eigen::Vector3f> vertices;  ///< m
  std::vector<Eigen::Vector3f> normals;   ///< one per vertex, outward
  std::vector<std::uint32_t> indices;     ///< triangles
  float cell_m = 0.0f;                    ///< grid cell used
  std::size_t grid_points = 0;            ///< grid points sampled
};

/// The surface around `centres` (m) of particles on a lattice of `spacing_m`. Empty when there
/// are no particles.
ParticleSurface particle_surface(std::span<const Eigen::Vector3f> centres, float spacing_m,
                                 const ParticleSurfaceOptions& options = {});

}  // namespace acdr
