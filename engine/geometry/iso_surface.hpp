// Closed triangle surfaces from implicit solids: sample a function f (negative inside) on a
// regular grid and extract its zero level set by marching tetrahedra. Each grid cube is split
// into the six Kuhn tetrahedra around its main diagonal; neighbouring cubes then share their
// face triangulations, the surface in each tetrahedron is one triangle or one quad, and
// crossing points are shared through their grid edge, so the result is closed and manifold
// whenever f is positive on the grid boundary (Doi & Koide 1991; Treece et al. 1999).
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "engine/geometry/triangle_mesh.hpp"

namespace acdr {

/// Samples of a scalar function on the points origin + (i, j, k) * spacing.
struct ScalarGrid {
  Vec3 origin_m = Vec3::Zero();
  double spacing_m = 1e-3;
  int nx = 0, ny = 0, nz = 0;
  std::vector<double> values;  ///< nx*ny*nz, x fastest: values[(k*ny + j)*nx + i]

  std::size_t index(int i, int j, int k) const {
    return (static_cast<std::size_t>(k) * ny + j) * nx + i;
  }
  Vec3 point(int i, int j, int k) const {
    return origin_m + spacing_m * Vec3(i, j, k);
  }
};

/// Samples `f` on a grid of `spacing_m` covering [min_m, max_m] (rounded outward to whole cells).
///
/// With `lipschitz` (f changes by at most the distance moved, as exact and blended distance
/// functions do) the grid is sampled coarse to fine: f is evaluated at the centre of each
/// block of 8^3 samples, and a block whose centre is farther from the surface than its
/// half-diagonal plus 1.5 spacings is filled with that value instead of being sampled. Its
/// samples then have the right sign and none of them touches a grid edge the surface
/// crosses, so the extracted surface is the same as from full sampling.
ScalarGrid sample_function(const std::function<double(const Vec3&)>& f, const Vec3& min_m,
                           const Vec3& max_m, double spacing_m, bool lipschitz = false);

/// The zero level set of the sampled function, counter-clockwise seen from where f > 0.
/// Samples equal to zero count as outside. Crossings are kept at least 1 % of an edge away
/// from the grid points, so no triangle degenerates.
TriangleMesh extract_iso_surface(const ScalarGrid& grid);

}  // namespace acdr
