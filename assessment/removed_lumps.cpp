// Single-linkage clusters with a cell grid and union-find.
#include "assessment/removed_lumps.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

namespace acdr {
namespace {

int find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

}  // namespace

LumpStats removed_lumps(std::span<const Eigen::Vector3f> positions, double link_m,
                        int min_particles) {
  LumpStats s;
  const int n = static_cast<int>(positions.size());
  s.particles = n;
  if (n == 0 || !(link_m > 0.0)) {
    s.clusters = n;
    s.largest = n > 0 ? 1 : 0;
    s.lumps = s.in_lumps = (n > 0 && min_particles <= 1) ? n : 0;
    return s;
  }
  // Cells of side link_m: a partner of a particle lies in its cell or one of the 26 around it.
  Eigen::Vector3d lo = positions[0].cast<double>();
  for (const Eigen::Vector3f& p : positions) lo = lo.cwiseMin(p.cast<double>());
  struct Entry {
    std::int64_t cell;
    int index;
  };
  auto cell_of = [&](const Eigen::Vector3f& p, int d[3]) {
    for (int a = 0; a < 3; ++a) d[a] = static_cast<int>(std::floor((p[a] - lo[a]) / link_m));
  };
  constexpr std::int64_t kSide = 1 << 20;  // cells per axis in the key (positions span < 1 km)
  auto key = [&](int i, int j, int k) { return (std::int64_t(k) * kSide + j) * kSide + i; };
  std::vector<Entry> sorted(n);
  for (int i = 0; i < n; ++i) {
    int d[3];
    cell_of(positions[i], d);
    sorted[i] = {key(d[0], d[1], d[2]), i};
  }
  std::sort(sorted.begin(), sorted.end(), [](const Entry& a, const Entry& b) {
    return a.cell != b.cell ? a.cell < b.cell : a.index < b.index;
  });
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  const double link2 = link_m * link_m;
  for (int i = 0; i < n; ++i) {
    int d[3];
    cell_of(positions[i], d);
    for (int dk = -1; dk <= 1; ++dk)
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          if (d[0] + di < 0 || d[1] + dj < 0 || d[2] + dk < 0) continue;
          const std::int64_t c = key(d[0] + di, d[1] + dj, d[2] + dk);
          auto it = std::lower_bound(sorted.begin(), sorted.end(), c,
                                     [](const Entry& e, std::int64_t v) { return e.cell < v; });
          for (; it != sorted.end() && it->cell == c; ++it) {
            const int j = it->index;
            if (j <= i) continue;
            if ((positions[j] - positions[i]).cast<double>().squaredNorm() >= link2) continue;
            const int ri = find_root(parent, i), rj = find_root(parent, j);
            if (ri != rj) parent[std::max(ri, rj)] = std::min(ri, rj);
          }
        }
  }
  std::vector<int> size(n, 0);
  for (int i = 0; i < n; ++i) ++size[find_root(parent, i)];
  for (int i = 0; i < n; ++i) {
    if (size[i] == 0) continue;
    ++s.clusters;
    s.largest = std::max(s.largest, size[i]);
    if (size[i] >= min_particles) {
      ++s.lumps;
      s.in_lumps += size[i];
    }
  }
  return s;
}

}  // namespace acdr
