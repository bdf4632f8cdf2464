// Hashed uniform grid: counting sort of particles into cell buckets.
#include "engine/nucleus/neighbor_grid.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace acdr {

void NeighborGrid::reserve(std::size_t capacity) {
  std::size_t table = 64;
  while (table < 2 * capacity) table *= 2;
  mask_ = static_cast<std::uint32_t>(table - 1);
  start_.assign(table + 1, 0);
  cell_.resize(capacity);
  sorted_.resize(capacity);
  bucket_of_.resize(capacity);
}

void NeighborGrid::build(std::span<const Vec3> x, double cell_m,
                         const std::array<bool, 3>& periodic, const Vec3& pmin,
                         const Vec3& pmax) {
  assert(x.size() <= cell_.size() && "NeighborGrid::reserve was not called with enough room");
  periodic_ = periodic;
  Vec3 edge = Vec3::Constant(cell_m);
  for (int a = 0; a < 3; ++a) {
    count_[a] = 0;
    if (!periodic[a]) continue;
    const double length = pmax[a] - pmin[a];
    count_[a] = std::max<std::int32_t>(1, static_cast<std::int32_t>(std::floor(length / cell_m)));
    edge[a] = length / count_[a];
  }
  std::fill(start_.begin(), start_.end(), 0u);
  for (std::size_t i = 0; i < x.size(); ++i) {
    std::array<std::int32_t, 3> c;
    for (int a = 0; a < 3; ++a) {
      const double origin = periodic[a] ? pmin[a] : 0.0;
      // Non-finite positions (a blow-up being reported) land in one far cell, never UB.
      const double u = std::floor((x[i][a] - origin) / edge[a]);
      c[a] = std::isfinite(u) ? static_cast<std::int32_t>(std::clamp(u, -1.0e9, 1.0e9))
                              : std::int32_t{1 << 30};
      if (periodic[a]) c[a] = wrap(c[a], count_[a]);
    }
    cell_[i] = c;
    bucket_of_[i] = bucket(c);
    ++start_[bucket_of_[i] + 1];
  }
  for (std::size_t b = 1; b < start_.size(); ++b) start_[b] += start_[b - 1];
  // Stable scatter: within a bucket, particles stay in index order (determinism). The last
  // bucket offsets are used as write cursors and restored afterwards.
  for (std::size_t i = 0; i < x.size(); ++i) sorted_[start_[bucket_of_[i]]++] = static_cast<std::int32_t>(i);
  for (std::size_t b = start_.size() - 1; b > 0; --b) start_[b] = start_[b - 1];
  start_[0] = 0;
}

}  // namespace acdr
