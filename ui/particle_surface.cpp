// Zhu-Bridson particle surface: splat the kernel sums onto a grid, extract, shade by gradient.
#include "ui/particle_surface.hpp"

#include <algorithm>
#include <cmath>

#include "engine/geometry/iso_surface.hpp"

namespace acdr {

ParticleSurface particle_surface(std::span<const Eigen::Vector3f> centres, float spacing_m,
                                 const ParticleSurfaceOptions& options) {
  ParticleSurface out;
  if (centres.empty() || !(spacing_m > 0.0f)) return out;
  const float r = options.radius_spacings * spacing_m;
  const float support = options.support_spacings * spacing_m;
  float cell = options.cell_spacings * spacing_m;

  // The grid covers the particles' bounds, grown by the support and a cell, so the field is
  // positive (outside) on its boundary and the surface closes.
  Eigen::Vector3f lo = centres[0], hi = centres[0];
  for (const Eigen::Vector3f& c : centres) {
    if (!c.allFinite()) continue;
    lo = lo.cwiseMin(c);
    hi = hi.cwiseMax(c);
  }
  if (!lo.allFinite() || !hi.allFinite()) return out;
  const Eigen::Vector3f margin = Eigen::Vector3f::Constant(support + cell);
  lo -= margin;
  hi += margin;
  const Eigen::Vector3f size = hi - lo;
  auto points_for = [&](float h) {
    return (std::ceil(size.x() / h) + 1.0) * (std::ceil(size.y() / h) + 1.0) *
           (std::ceil(size.z() / h) + 1.0);
  };
  while (points_for(cell) > static_cast<double>(options.max_grid_points)) cell *= 1.25f;

  ScalarGrid grid;
  grid.origin_m = lo.cast<double>();
  grid.spacing_m = cell;
  grid.nx = static_cast<int>(std::ceil(size.x() / cell)) + 1;
  grid.ny = static_cast<int>(std::ceil(size.y() / cell)) + 1;
  grid.nz = static_cast<int>(std::ceil(size.z() / cell)) + 1;
  const std::size_t n = static_cast<std::size_t>(grid.nx) * grid.ny * grid.nz;
  out.cell_m = cell;
  out.grid_points = n;

  // Kernel sums: sum w and sum w x (centres relative to the grid origin, for precision).
  std::vector<float> wsum(n, 0.0f);
  std::vector<Eigen::Vector3f> wx(n, Eigen::Vector3f::Zero());
  std::vector<float> nearest2(n, support * support);  // squared distance to the nearest centre
  const float inv_support2 = 1.0f / (support * support);
  const int reach = static_cast<int>(std::ceil(support / cell));
  for (const Eigen::Vector3f& c : centres) {
    if (!c.allFinite()) continue;
    const Eigen::Vector3f local = c - lo;
    const int ci = static_cast<int>(std::lround(local.x() / cell));
    const int cj = static_cast<int>(std::lround(local.y() / cell));
    const int ck = static_cast<int>(std::lround(local.z() / cell));
    for (int k = std::max(ck - reach, 0); k <= std::min(ck + reach, grid.nz - 1); ++k) {
      for (int j = std::max(cj - reach, 0); j <= std::min(cj + reach, grid.ny - 1); ++j) {
        for (int i = std::max(ci - reach, 0); i <= std::min(ci + reach, grid.nx - 1); ++i) {
          const Eigen::Vector3f d = Eigen::Vector3f(i * cell, j * cell, k * cell) - local;
          const float q = 1.0f - d.squaredNorm() * inv_support2;
          if (q <= 0.0f) continue;
          const float w = q * q * q;
          const std::size_t at = grid.index(i, j, k);
          wsum[at] += w;
          wx[at] += w * local;
          nearest2[at] = std::min(nearest2[at], d.squaredNorm());
        }
      }
    }
  }
  // phi = |x - xbar| - r where any particle is near, else the support (plainly outside); never
  // inside farther than half the join distance from every centre.
  const float half_join = 0.5f * options.join_spacings * spacing_m;
  grid.values.resize(n);
  for (int k = 0; k < grid.nz; ++k)
    for (int j = 0; j < grid.ny; ++j)
      for (int i = 0; i < grid.nx; ++i) {
        const std::size_t at = grid.index(i, j, k);
        if (wsum[at] <= 0.0f) {
          grid.values[at] = support;
          continue;
        }
        const Eigen::Vector3f xbar = wx[at] / wsum[at];
        const float zhu_bridson = (Eigen::Vector3f(i * cell, j * cell, k * cell) - xbar).norm() - r;
        grid.values[at] = std::max(zhu_bridson, std::sqrt(nearest2[at]) - half_join);
      }

  const TriangleMesh mesh = extract_iso_surface(grid);
  out.vertices.reserve(mesh.vertices.size());
  for (const Vec3& v : mesh.vertices) out.vertices.push_back(v.cast<float>());
  out.indices.reserve(3 * mesh.triangles.size());
  for (const auto& t : mesh.triangles) out.indices.insert(out.indices.end(), t.begin(), t.end());

  // Normals: the field's gradient (central differences at the grid points, one-sided at the
  // border), interpolated trilinearly to each vertex.
  auto value = [&](int i, int j, int k) {
    i = std::clamp(i, 0, grid.nx - 1), j = std::clamp(j, 0, grid.ny - 1), k = std::clamp(k, 0, grid.nz - 1);
    return static_cast<float>(grid.values[grid.index(i, j, k)]);
  };
  auto gradient_at = [&](int i, int j, int k) {
    return Eigen::Vector3f(value(i + 1, j, k) - value(i - 1, j, k),
                           value(i, j + 1, k) - value(i, j - 1, k),
                           value(i, j, k + 1) - value(i, j, k - 1));
  };
  out.normals.resize(out.vertices.size());
  for (std::size_t v = 0; v < out.vertices.size(); ++v) {
    const Eigen::Vector3f g = (out.vertices[v] - lo) / cell;
    const int i = std::clamp(static_cast<int>(std::floor(g.x())), 0, grid.nx - 2);
    const int j = std::clamp(static_cast<int>(std::floor(g.y())), 0, grid.ny - 2);
    const int k = std::clamp(static_cast<int>(std::floor(g.z())), 0, grid.nz - 2);
    const Eigen::Vector3f t = (g - Eigen::Vector3f(i, j, k)).cwiseMax(0.0f).cwiseMin(1.0f);
    Eigen::Vector3f sum = Eigen::Vector3f::Zero();
    for (int c = 0; c < 8; ++c) {
      const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
      const float w = (di ? t.x() : 1 - t.x()) * (dj ? t.y() : 1 - t.y()) * (dk ? t.z() : 1 - t.z());
      sum += w * gradient_at(i + di, j + dj, k + dk);
    }
    out.normals[v] = sum.squaredNorm() > 0.0f ? sum.normalized() : Eigen::Vector3f::UnitZ();
  }
  return out;
}

}  // namespace acdr
