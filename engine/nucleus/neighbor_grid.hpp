// A hashed uniform grid for fixed-radius neighbour search (Teschner et al., "Optimized spatial
// hashing for collision detection of deformable objects", VMV 2003): particles are counting-
// sorted into hash buckets of cubic cells no smaller than the search radius, so a query visits
// 27 cells. Unbounded domains cost nothing extra (material lifted far away still hashes), the
// table is sized once, building allocates nothing, and the order is deterministic (stable
// counting sort by particle index).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "engine/core/types.hpp"

namespace acdr {

class NeighborGrid {
 public:
  /// Sizes the table for up to `capacity` particles (allocates; call once).
  void reserve(std::size_t capacity);

  /// Sorts the particles into cells of edge >= `cell_m`. Along a periodic axis the domain
  /// [pmin, pmax) is split into a whole number of cells and cell indices wrap.
  void build(std::span<const Vec3> x, double cell_m, const std::array<bool, 3>& periodic,
             const Vec3& pmin, const Vec3& pmax);

  /// Calls f(j) for every particle j in the 27 cells around particle i's cell (i included).
  template <class F>
  void for_each_candidate(std::size_t i, F&& f) const {
    const std::array<std::int32_t, 3> c = cell_[i];
    std::array<std::int32_t, 3> lo, hi;
    for (int a = 0; a < 3; ++a) {
      lo[a] = -1;
      hi[a] = 1;
      // With fewer than 3 cells on a periodic axis, offsets wrap onto the same cell: visit
      // each distinct cell once.
      if (periodic_[a] && count_[a] < 3) {
        lo[a] = 0;
        hi[a] = count_[a] - 1;
      }
    }
    for (int dz = lo[2]; dz <= hi[2]; ++dz)
      for (int dy = lo[1]; dy <= hi[1]; ++dy)
        for (int dx = lo[0]; dx <= hi[0]; ++dx) {
          std::array<std::int32_t, 3> q = {c[0] + dx, c[1] + dy, c[2] + dz};
          for (int a = 0; a < 3; ++a)
            if (periodic_[a]) q[a] = wrap(q[a], count_[a]);
          const std::uint32_t b = bucket(q);
          for (std::uint32_t k = start_[b]; k < start_[b + 1]; ++k) {
            const std::int32_t j = sorted_[k];
            const auto& cj = cell_[j];
            if (cj[0] == q[0] && cj[1] == q[1] && cj[2] == q[2]) f(static_cast<std::size_t>(j));
          }
        }
  }

 private:
  static std::int32_t wrap(std::int32_t v, std::int32_t n) {
    v %= n;
    return v < 0 ? v + n : v;
  }
  std::uint32_t bucket(const std::array<std::int32_t, 3>& c) const {
    const std::uint32_t h = static_cast<std::uint32_t>(c[0]) * 73856093u ^
                            static_cast<std::uint32_t>(c[1]) * 19349663u ^
                            static_cast<std::uint32_t>(c[2]) * 83492791u;
    return h & mask_;
  }

  std::vector<std::array<std::int32_t, 3>> cell_;  // N, integer cell coordinates
  std::vector<std::uint32_t> start_;               // table + 1, bucket offsets into sorted_
  std::vector<std::int32_t> sorted_;               // N, particle indices by bucket
  std::vector<std::uint32_t> bucket_of_;           // N
  std::uint32_t mask_ = 0;
  std::array<bool, 3> periodic_ = {false, false, false};
  std::array<std::int32_t, 3> count_ = {0, 0, 0};
};

}  // namespace acdr
