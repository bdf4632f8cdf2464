// Marching tetrahedra over a Kuhn (Freudenthal) subdivision of the sampling grid.
#include "engine/geometry/iso_surface.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <unordered_map>

namespace acdr {

ScalarGrid sample_function(const std::function<double(const Vec3&)>& f, const Vec3& min_m,
                           const Vec3& max_m, double spacing_m, bool lipschitz) {
  ScalarGrid g;
  g.spacing_m = spacing_m;
  g.origin_m = min_m;
  const Vec3 size = max_m - min_m;
  g.nx = static_cast<int>(std::ceil(size.x() / spacing_m)) + 1;
  g.ny = static_cast<int>(std::ceil(size.y() / spacing_m)) + 1;
  g.nz = static_cast<int>(std::ceil(size.z() / spacing_m)) + 1;
  g.values.resize(static_cast<std::size_t>(g.nx) * g.ny * g.nz);
  if (!lipschitz) {
    for (int k = 0; k < g.nz; ++k)
      for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) g.values[g.index(i, j, k)] = f(g.point(i, j, k));
    return g;
  }
  constexpr int kBlock = 8;
  for (int k0 = 0; k0 < g.nz; k0 += kBlock) {
    for (int j0 = 0; j0 < g.ny; j0 += kBlock) {
      for (int i0 = 0; i0 < g.nx; i0 += kBlock) {
        const int i1 = std::min(i0 + kBlock, g.nx), j1 = std::min(j0 + kBlock, g.ny),
                  k1 = std::min(k0 + kBlock, g.nz);
        const Vec3 lo = g.point(i0, j0, k0), hi = g.point(i1 - 1, j1 - 1, k1 - 1);
        const double centre_value = f(0.5 * (lo + hi));
        const bool far = std::abs(centre_value) > 0.5 * (hi - lo).norm() + 1.5 * spacing_m;
        for (int k = k0; k < k1; ++k)
          for (int j = j0; j < j1; ++j)
            for (int i = i0; i < i1; ++i)
              g.values[g.index(i, j, k)] = far ? centre_value : f(g.point(i, j, k));
      }
    }
  }
  return g;
}

namespace {

// Cube corner c has offset (c & 1, (c >> 1) & 1, (c >> 2) & 1). The six tetrahedra follow the
// monotone paths 0 -> 7 through one, then two axis steps; all contain the diagonal 0-7.
constexpr std::array<std::array<int, 4>, 6> kTets = {{
    {0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}}};

constexpr double kMinFraction = 0.01;  // crossing kept within [1 %, 99 %] of its edge

}  // namespace

TriangleMesh extract_iso_surface(const ScalarGrid& g) {
  TriangleMesh mesh;
  if (g.nx < 2 || g.ny < 2 || g.nz < 2) return mesh;
  const auto n_points = static_cast<std::uint64_t>(g.nx) * g.ny * g.nz;
  const double h = g.spacing_m;

  // One vertex per crossed grid edge, found again by its (lower, upper) point index pair. The
  // map is only looked up, never iterated: numbering follows the deterministic cube order.
  std::unordered_map<std::uint64_t, std::uint32_t> edge_vertex;
  auto edge_point = [&](std::uint64_t a, Vec3 pa, double fa, std::uint64_t b, Vec3 pb,
                        double fb) -> std::uint32_t {
    // Canonical direction, so both tetrahedra sharing the edge compute the same point.
    if (a > b) {
      std::swap(a, b);
      std::swap(pa, pb);
      std::swap(fa, fb);
    }
    const auto [it, inserted] =
        edge_vertex.try_emplace(a * n_points + b, static_cast<std::uint32_t>(mesh.vertices.size()));
    if (inserted) {
      const double t = std::clamp(fa / (fa - fb), kMinFraction, 1.0 - kMinFraction);
      mesh.vertices.push_back(pa + t * (pb - pa));
    }
    return it->second;
  };
  // Adds triangle (u, v, w) facing along `outward` (the direction f increases).
  auto emit = [&](std::uint32_t u, std::uint32_t v, std::uint32_t w, const Vec3& outward) {
    const Vec3 n = (mesh.vertices[v] - mesh.vertices[u]).cross(mesh.vertices[w] - mesh.vertices[u]);
    if (n.dot(outward) >= 0.0) {
      mesh.triangles.push_back({u, v, w});
    } else {
      mesh.triangles.push_back({u, w, v});
    }
  };

  std::array<std::uint64_t, 8> idx;
  std::array<Vec3, 8> p;
  std::array<double, 8> f;
  for (int k = 0; k + 1 < g.nz; ++k) {
    for (int j = 0; j + 1 < g.ny; ++j) {
      for (int i = 0; i + 1 < g.nx; ++i) {
        int inside = 0;
        for (int c = 0; c < 8; ++c) {
          const int ci = i + (c & 1), cj = j + ((c >> 1) & 1), ck = k + ((c >> 2) & 1);
          idx[c] = g.index(ci, cj, ck);
          const double v = g.values[idx[c]];
          f[c] = v == 0.0 ? 1e-300 : v;  // zero counts as outside
          inside += f[c] < 0.0;
        }
        if (inside == 0 || inside == 8) continue;
        for (int c = 0; c < 8; ++c) p[c] = g.point(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));

        for (const auto& tet : kTets) {
          int in[4], out[4], n_in = 0, n_out = 0;
          for (int c : tet) (f[c] < 0.0 ? in[n_in++] : out[n_out++]) = c;
          if (n_in == 0 || n_out == 0) continue;
          // Gradient of the linear interpolant: one axis step per edge of the path 0-c1-c2-7.
          Vec3 grad;
          grad[std::countr_zero(static_cast<unsigned>(tet[1]))] = (f[tet[1]] - f[tet[0]]) / h;
          grad[std::countr_zero(static_cast<unsigned>(tet[2] ^ tet[1]))] = (f[tet[2]] - f[tet[1]]) / h;
          grad[std::countr_zero(static_cast<unsigned>(tet[3] ^ tet[2]))] = (f[tet[3]] - f[tet[2]]) / h;
          auto ep = [&](int a, int b) { return edge_point(idx[a], p[a], f[a], idx[b], p[b], f[b]); };
          if (n_in == 1 || n_out == 1) {
            // One corner apart from the other three: a triangle around it.
            const int s = n_in == 1 ? in[0] : out[0];
            const int* o = n_in == 1 ? out : in;
            emit(ep(s, o[0]), ep(s, o[1]), ep(s, o[2]), grad);
          } else {
            // Two and two: a quad through the four crossed edges, cut along its shorter diagonal.
            const std::uint32_t q0 = ep(in[0], out[0]), q1 = ep(in[0], out[1]),
                                q2 = ep(in[1], out[1]), q3 = ep(in[1], out[0]);
            const double d02 = (mesh.vertices[q0] - mesh.vertices[q2]).squaredNorm();
            const double d13 = (mesh.vertices[q1] - mesh.vertices[q3]).squaredNorm();
            if (d02 <= d13) {
              emit(q0, q1, q2, grad);
              emit(q0, q2, q3, grad);
            } else {
              emit(q0, q1, q3, grad);
              emit(q1, q2, q3, grad);
            }
          }
        }
      }
    }
  }
  return mesh;
}

}  // namespace acdr
