// Structured tetrahedral box.
#include "engine/bone/box_tet_mesh.hpp"

#include <algorithm>
#include <cassert>

namespace acdr {

TetMesh make_box_tet_mesh(const Vec3& lo, const Vec3& hi, const std::array<int, 3>& n) {
  assert(n[0] > 0 && n[1] > 0 && n[2] > 0);
  TetMesh m;
  auto id = [&](int i, int j, int k) {
    return static_cast<std::uint32_t>((k * (n[1] + 1) + j) * (n[0] + 1) + i);
  };
  for (int k = 0; k <= n[2]; ++k)
    for (int j = 0; j <= n[1]; ++j)
      for (int i = 0; i <= n[0]; ++i) {
        const Vec3 f(double(i) / n[0], double(j) / n[1], double(k) / n[2]);
        m.nodes.push_back(lo + f.cwiseProduct(hi - lo));
      }
  // The six axis orders: walking from corner (0,0,0) to (1,1,1) one axis at a time.
  std::array<int, 3> axes = {0, 1, 2};
  std::array<std::array<int, 3>, 6> orders;
  int count = 0;
  do orders[count++] = axes;
  while (std::next_permutation(axes.begin(), axes.end()));
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i)
        for (const auto& order : orders) {
          std::array<int, 3> c = {i, j, k};
          std::array<std::uint32_t, 4> tet;
          tet[0] = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[order[s]];
            tet[s + 1] = id(c[0], c[1], c[2]);
          }
          m.tets.push_back(tet);
          if (m.tet_volume(m.tets.size() - 1) < 0.0) std::swap(m.tets.back()[2], m.tets.back()[3]);
        }
  m.region.assign(m.tets.size(), 0);
  return m;
}

}  // namespace acdr
