// Rasterising projected triangles into covered cells, then runs.
#include "ui/mesh_silhouette.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace acdr {

MeshSilhouette project_silhouette(const std::vector<const TriangleMesh*>& meshes, int ax, int ay,
                                  double cell_m) {
  MeshSilhouette s;
  s.ax = ax;
  s.ay = ay;
  s.cell_m = cell_m;
  double lo_a = std::numeric_limits<double>::infinity(), lo_b = lo_a, hi_a = -lo_a, hi_b = -lo_a;
  for (const TriangleMesh* m : meshes)
    for (const Vec3& v : m->vertices) {
      lo_a = std::min(lo_a, v[ax]), hi_a = std::max(hi_a, v[ax]);
      lo_b = std::min(lo_b, v[ay]), hi_b = std::max(hi_b, v[ay]);
    }
  if (!(cell_m > 0.0) || !(hi_a >= lo_a) || !(hi_b >= lo_b)) return s;
  s.origin_a = lo_a;
  s.origin_b = lo_b;
  const int nx = static_cast<int>(std::ceil((hi_a - lo_a) / cell_m)) + 1;
  const int ny = static_cast<int>(std::ceil((hi_b - lo_b) / cell_m)) + 1;
  std::vector<unsigned char> covered(static_cast<std::size_t>(nx) * ny, 0);
  for (const TriangleMesh* m : meshes) {
    for (const auto& t : m->triangles) {
      double a[3], b[3];
      for (int k = 0; k < 3; ++k) {
        a[k] = (m->vertices[t[k]][ax] - lo_a) / cell_m - 0.5;  // in cell-centre units
        b[k] = (m->vertices[t[k]][ay] - lo_b) / cell_m - 0.5;
      }
      const double area = (a[1] - a[0]) * (b[2] - b[0]) - (a[2] - a[0]) * (b[1] - b[0]);
      if (std::abs(area) < 1e-12) continue;  // seen edge on
      const int i0 = std::max(0, static_cast<int>(std::ceil(std::min({a[0], a[1], a[2]}))));
      const int i1 = std::min(nx - 1, static_cast<int>(std::floor(std::max({a[0], a[1], a[2]}))));
      const int j0 = std::max(0, static_cast<int>(std::ceil(std::min({b[0], b[1], b[2]}))));
      const int j1 = std::min(ny - 1, static_cast<int>(std::floor(std::max({b[0], b[1], b[2]}))));
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) {
          // Edge functions, signed by the triangle's winding as projected.
          bool inside = true;
          for (int e = 0; e < 3 && inside; ++e) {
            const int f = (e + 1) % 3;
            const double w = (a[f] - a[e]) * (j - b[e]) - (b[f] - b[e]) * (i - a[e]);
            inside = area > 0 ? w >= 0 : w <= 0;
          }
          if (inside) covered[static_cast<std::size_t>(j) * nx + i] = 1;
        }
    }
  }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx;) {
      if (!covered[static_cast<std::size_t>(j) * nx + i]) {
        ++i;
        continue;
      }
      MeshSilhouette::Run r;
      r.row = j;
      r.first = i;
      while (i < nx && covered[static_cast<std::size_t>(j) * nx + i]) ++i;
      r.last = i - 1;
      s.runs.push_back(r);
    }
  return s;
}

}  // namespace acdr
