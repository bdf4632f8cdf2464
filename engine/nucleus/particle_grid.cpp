// Dense particle grid: bounding box, cell size, counting sort by cell.
#include "engine/nucleus/particle_grid.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace acdr {

void ParticleGrid::reserve(std::size_t capacity) {
  // Room for a few cells per particle: a bounding box much emptier than that gets larger
  // cells instead (still exact, only slower to query).
  max_cells_ = std::max<std::size_t>(4096, 8 * capacity);
  start_.assign(max_cells_ + 1, 0);
  sorted_.assign(capacity, 0);
  xx_.assign(capacity, 0.0);
  xy_.assign(capacity, 0.0);
  xz_.assign(capacity, 0.0);
  cell_of_.assign(capacity, 0);
}

void ParticleGrid::build(std::span<const Vec3> x, double cell_m,
                         const std::array<bool, 3>& periodic, const Vec3& pmin,
                         const Vec3& pmax) {
  assert(x.size() <= sorted_.size() && "ParticleGrid::reserve was not called with enough room");
  periodic_ = periodic;
  // Bounding box of the finite positions.
  Vec3 lo = Vec3::Constant(0.0), hi = Vec3::Constant(0.0);
  bool any = false;
  for (const Vec3& p : x) {
    if (!(std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()))) continue;
    if (!any) {
      lo = hi = p;
      any = true;
    } else {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  // Cell edge: at least cell_m, grown until the box fits the cell budget.
  double edge = cell_m;
  for (;;) {
    std::size_t cells = 1;
    for (int a = 0; a < 3; ++a) {
      std::int32_t n;
      if (periodic[a]) {
        n = std::max<std::int32_t>(
            1, static_cast<std::int32_t>(std::floor((pmax[a] - pmin[a]) / edge)));
      } else {
        n = static_cast<std::int32_t>(std::min(1.0e6, std::floor((hi[a] - lo[a]) / edge))) + 1;
      }
      count_[a] = n;
      cells *= static_cast<std::size_t>(n);
    }
    if (cells <= max_cells_) {
      cells_ = cells;
      break;
    }
    edge *= 1.25;
  }
  for (int a = 0; a < 3; ++a) {
    if (periodic[a]) {
      origin_[a] = pmin[a];
      inv_edge_[a] = count_[a] / (pmax[a] - pmin[a]);
    } else {
      origin_[a] = lo[a];
      inv_edge_[a] = 1.0 / edge;
    }
  }
  // Counting sort by linear cell index (x fastest); stable in particle index.
  std::fill(start_.begin(), start_.begin() + cells_ + 1, 0u);
  for (std::size_t i = 0; i < x.size(); ++i) {
    const std::uint32_t c =
        (static_cast<std::uint32_t>(coord(x[i].z(), 2)) * count_[1] + coord(x[i].y(), 1)) *
            count_[0] +
        coord(x[i].x(), 0);
    cell_of_[i] = c;
    ++start_[c + 1];
  }
  for (std::size_t c = 1; c <= cells_; ++c) start_[c] += start_[c - 1];
  for (std::size_t i = 0; i < x.size(); ++i) {
    const std::uint32_t k = start_[cell_of_[i]]++;
    sorted_[k] = static_cast<std::int32_t>(i);
    xx_[k] = x[i].x();
    xy_[k] = x[i].y();
    xz_[k] = x[i].z();
  }
  for (std::size_t c = cells_; c > 0; --c) start_[c] = start_[c - 1];
  start_[0] = 0;
}

}  // namespace acdr
