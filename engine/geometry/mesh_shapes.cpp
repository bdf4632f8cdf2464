// Box and icosphere meshes.
#include "engine/geometry/mesh_shapes.hpp"

#include <cmath>
#include <map>
#include <utility>

namespace acdr {

TriangleMesh make_box_mesh(const Vec3& lo, const Vec3& hi) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) {
    m.vertices.emplace_back((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(),
                            (i & 4) ? hi.z() : lo.z());
  }
  // Two triangles per face, counter-clockwise seen from outside.
  m.triangles = {{0, 2, 1}, {1, 2, 3},   // z = lo
                 {4, 5, 6}, {5, 7, 6},   // z = hi
                 {0, 1, 4}, {1, 5, 4},   // y = lo
                 {2, 6, 3}, {3, 6, 7},   // y = hi
                 {0, 4, 2}, {2, 4, 6},   // x = lo
                 {1, 3, 5}, {3, 7, 5}};  // x = hi
  return m;
}

TriangleMesh make_sphere_mesh(const Vec3& center, double radius, int subdivisions) {
  // Unit icosahedron: 12 vertices (0, ±1, ±phi) and cyclic permutations.
  const double phi = 0.5 * (1.0 + std::sqrt(5.0));
  std::vector<Vec3> v = {{-1, phi, 0}, {1, phi, 0},  {-1, -phi, 0}, {1, -phi, 0},
                         {0, -1, phi}, {0, 1, phi},  {0, -1, -phi}, {0, 1, -phi},
                         {phi, 0, -1}, {phi, 0, 1},  {-phi, 0, -1}, {-phi, 0, 1}};
  for (Vec3& p : v) p.normalize();
  std::vector<std::array<std::uint32_t, 3>> f = {
      {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    // Split each triangle in four; the midpoint of a shared edge is made once.
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      auto [it, inserted] = mid.try_emplace(key, static_cast<std::uint32_t>(v.size()));
      if (inserted) v.push_back((v[a] + v[b]).normalized());
      return it->second;
    };
    std::vector<std::array<std::uint32_t, 3>> next;
    next.reserve(4 * f.size());
    for (const auto& t : f) {
      const std::uint32_t ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]),
                          ca = midpoint(t[2], t[0]);
      next.push_back({t[0], ab, ca});
      next.push_back({t[1], bc, ab});
      next.push_back({t[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    f = std::move(next);
  }
  TriangleMesh m;
  m.vertices.reserve(v.size());
  for (const Vec3& p : v) m.vertices.push_back(center + radius * p);
  m.triangles = std::move(f);
  return m;
}

}  // namespace acdr
