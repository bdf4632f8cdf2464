// A dense uniform grid over the particles' bounding box for neighbour rows and box queries.
// Particles are counting-sorted by cell (x fastest), and their positions are copied in that
// order, so the 27 cells around a point are 9 contiguous runs of memory (the layout of
// Green, "Particle simulation using CUDA", NVIDIA 2010, and of most SPH codes). Cell indices
// are clamped at the box: clamping keeps neighbouring points in neighbouring cells, so queries
// stay exact even for a particle flung far away (it only crowds a border cell). Periodic axes
// split [pmin, pmax) into whole cells and wrap. Building allocates nothing once reserved; the
// order is deterministic (stable counting sort by particle index).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include <immintrin.h>

#include "engine/core/types.hpp"

namespace acdr {

class ParticleGrid {
 public:
  /// Sizes the arrays for up to `capacity` particles (allocates; call once).
  void reserve(std::size_t capacity);

  /// Sorts `x` into cubic cells of edge >= `cell_m` (larger when the bounding box would need
  /// more cells than the capacity allows).
  void build(std::span<const Vec3> x, double cell_m, const std::array<bool, 3>& periodic,
             const Vec3& pmin, const Vec3& pmax);

  /// Calls f(j, x_j) for every particle j in the 27 cells around p (p's own cell
  /// included; each particle once). x_j is the position given to build().
  template <class F>
  void for_each_near(const Vec3& p, F&& f) const {
    for_each_run_near(p, [&](std::uint32_t first, std::uint32_t end) {
      for (std::uint32_t k = first; k < end; ++k) f(sorted_[k], position(k));
    });
  }

  /// Calls f(j, r2) for every particle j in the 27 cells around p whose squared distance
  /// r2 from p is below r2_max, in the order for_each_near visits them. r2 is summed as
  /// (dx^2 + dy^2) + dz^2, the order of a Vec3's squaredNorm(), so it has the same bits as
  /// (x_j - p).squaredNorm(); four candidates are tested at a time (two on the baseline
  /// path). Grids without periodic axes only (the distance is not the minimum image).
  template <class F>
  void for_each_within(const Vec3& p, double r2_max, F&& f) const {
    const double* X = xx_.data();
    const double* Y = xy_.data();
    const double* Z = xz_.data();
    for_each_run_near(p, [&](std::uint32_t first, std::uint32_t end) {
      std::uint32_t k = first;
#if defined(__AVX__)
      const __m256d px = _mm256_set1_pd(p.x()), py = _mm256_set1_pd(p.y()),
                    pz = _mm256_set1_pd(p.z()), lim = _mm256_set1_pd(r2_max);
      for (; k + 4 <= end; k += 4) {
        const __m256d dx = _mm256_sub_pd(_mm256_loadu_pd(X + k), px);
        const __m256d dy = _mm256_sub_pd(_mm256_loadu_pd(Y + k), py);
        const __m256d dz = _mm256_sub_pd(_mm256_loadu_pd(Z + k), pz);
        const __m256d r2 = _mm256_add_pd(
            _mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)), _mm256_mul_pd(dz, dz));
        unsigned m = static_cast<unsigned>(_mm256_movemask_pd(_mm256_cmp_pd(r2, lim, _CMP_LT_OQ)));
        if (m == 0) continue;
        alignas(32) double r[4];
        _mm256_store_pd(r, r2);
        for (; m != 0; m &= m - 1) {
          const unsigned b = static_cast<unsigned>(__builtin_ctz(m));
          f(sorted_[k + b], r[b]);
        }
      }
#else
      const __m128d px = _mm_set1_pd(p.x()), py = _mm_set1_pd(p.y()), pz = _mm_set1_pd(p.z()),
                    lim = _mm_set1_pd(r2_max);
      for (; k + 2 <= end; k += 2) {
        const __m128d dx = _mm_sub_pd(_mm_loadu_pd(X + k), px);
        const __m128d dy = _mm_sub_pd(_mm_loadu_pd(Y + k), py);
        const __m128d dz = _mm_sub_pd(_mm_loadu_pd(Z + k), pz);
        const __m128d r2 =
            _mm_add_pd(_mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy)), _mm_mul_pd(dz, dz));
        const int m = _mm_movemask_pd(_mm_cmplt_pd(r2, lim));
        if (m == 0) continue;
        alignas(16) double r[2];
        _mm_store_pd(r, r2);
        if (m & 1) f(sorted_[k], r[0]);
        if (m & 2) f(sorted_[k + 1], r[1]);
      }
#endif
      for (; k < end; ++k) {
        const double dx = X[k] - p.x(), dy = Y[k] - p.y(), dz = Z[k] - p.z();
        const double r2 = (dx * dx + dy * dy) + dz * dz;
        if (r2 < r2_max) f(sorted_[k], r2);
      }
    });
  }

  /// Calls f(j, x_j) for every particle in the cells overlapping the box [lo, hi] (a superset
  /// of the particles inside it).
  template <class F>
  void for_each_in_box(const Vec3& lo, const Vec3& hi, F&& f) const {
    std::array<std::int32_t, 3> a0, a1;
    for (int a = 0; a < 3; ++a) {
      if (periodic_[a]) {
        a0[a] = 0;
        a1[a] = count_[a] - 1;
      } else {
        a0[a] = coord(lo[a], a);
        a1[a] = coord(hi[a], a);
      }
    }
    for (std::int32_t z = a0[2]; z <= a1[2]; ++z)
      for (std::int32_t y = a0[1]; y <= a1[1]; ++y) {
        const std::uint32_t row = (static_cast<std::uint32_t>(z) * count_[1] + y) * count_[0];
        run(row + a0[0], row + a1[0], f);
      }
  }

  std::size_t cell_count() const { return cells_; }

 private:
  // The position given to build() of the k-th sorted particle.
  Vec3 position(std::uint32_t k) const { return Vec3(xx_[k], xy_[k], xz_[k]); }
  template <class F>
  void run(std::uint32_t first_cell, std::uint32_t last_cell, F& f) const {
    const std::uint32_t end = start_[last_cell + 1];
    for (std::uint32_t k = start_[first_cell]; k < end; ++k) f(sorted_[k], position(k));
  }
  // Calls g(first, end) for each run of sorted entries [first, end) in the 27 cells around
  // p, in z, y, x order of the cells (9 runs, more where a periodic x axis wraps).
  template <class G>
  void for_each_run_near(const Vec3& p, G&& g) const {
    std::array<std::int32_t, 3> c;
    for (int a = 0; a < 3; ++a) c[a] = coord(p[a], a);
    std::array<std::int32_t, 3> lo, hi;
    for (int a = 0; a < 3; ++a) {
      lo[a] = c[a] - 1;
      hi[a] = c[a] + 1;
      if (periodic_[a]) {
        if (count_[a] < 3) {  // offsets would wrap onto the same cell: each cell once
          lo[a] = 0;
          hi[a] = count_[a] - 1;
        }
      } else {
        lo[a] = lo[a] < 0 ? 0 : lo[a];
        hi[a] = hi[a] >= count_[a] ? count_[a] - 1 : hi[a];
      }
    }
    for (std::int32_t z = lo[2]; z <= hi[2]; ++z) {
      const std::int32_t zz = wrap(z, 2);
      for (std::int32_t y = lo[1]; y <= hi[1]; ++y) {
        const std::int32_t yy = wrap(y, 1);
        const std::uint32_t row = (static_cast<std::uint32_t>(zz) * count_[1] + yy) * count_[0];
        if (!periodic_[0] || count_[0] < 3) {
          g(start_[row + lo[0]], start_[row + hi[0] + 1]);
        } else {
          // Up to two runs when the x offsets wrap around the periodic box.
          for (std::int32_t x = lo[0]; x <= hi[0]; ++x) {
            const std::uint32_t cell = row + wrap(x, 0);
            g(start_[cell], start_[cell + 1]);
          }
        }
      }
    }
  }
  std::int32_t coord(double v, int a) const {
    const double u = (v - origin_[a]) * inv_edge_[a];
    // Non-finite positions (a blow-up being reported) land in cell 0, never UB.
    if (!(u > -1.0e9 && u < 1.0e9)) return 0;
    std::int32_t c = static_cast<std::int32_t>(std::floor(u));
    if (periodic_[a]) {
      c %= count_[a];
      return c < 0 ? c + count_[a] : c;
    }
    return c < 0 ? 0 : (c >= count_[a] ? count_[a] - 1 : c);
  }
  std::int32_t wrap(std::int32_t c, int a) const {
    if (!periodic_[a]) return c;
    c %= count_[a];
    return c < 0 ? c + count_[a] : c;
  }

  std::array<bool, 3> periodic_ = {false, false, false};
  std::array<std::int32_t, 3> count_ = {1, 1, 1};
  Vec3 origin_ = Vec3::Zero();
  Vec3 inv_edge_ = Vec3::Ones();
  std::size_t cells_ = 1;
  std::size_t max_cells_ = 1;
  std::vector<std::uint32_t> start_;     // cells + 1, offsets into sorted_
  std::vector<std::int32_t> sorted_;     // N, particle indices by cell
  std::vector<double> xx_, xy_, xz_;     // N, their positions by coordinate
  std::vector<std::uint32_t> cell_of_;   // N, scratch
};

}  // namespace acdr
