// Boundary faces in buckets: counting sort by cell, then box queries.
#include "engine/bone/boundary_surface.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/geometry/signed_distance_grid.hpp"

namespace acdr {

BoundarySurface::BoundarySurface(const TetMesh& mesh) : nodes_(&mesh.nodes) {
  faces_ = boundary_faces(mesh);
  const auto& x = mesh.nodes;
  area_.resize(faces_.size());
  normal_.resize(faces_.size());
  on_surface_.assign(x.size(), 0);
  double edges = 0.0;
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (std::size_t f = 0; f < faces_.size(); ++f) {
    const auto& n = faces_[f].nodes;
    const Vec3 c = (x[n[1]] - x[n[0]]).cross(x[n[2]] - x[n[0]]);
    area_[f] = 0.5 * c.norm();
    normal_[f] = area_[f] > 0.0 ? Vec3(c.normalized()) : Vec3::Zero();
    edges += (x[n[1]] - x[n[0]]).norm() + (x[n[2]] - x[n[1]]).norm() + (x[n[0]] - x[n[2]]).norm();
    for (std::uint32_t i : n) {
      on_surface_[i] = 1;
      lo = lo.cwiseMin(x[i]);
      hi = hi.cwiseMax(x[i]);
    }
  }
  if (faces_.empty()) {
    bucket_start_.assign(2, 0);
    return;
  }
  mean_edge_ = edges / (3.0 * static_cast<double>(faces_.size()));
  cell_ = 2.0 * mean_edge_;
  origin_ = lo;
  for (int k = 0; k < 3; ++k)
    dims_[k] = std::max(1, static_cast<int>(std::ceil((hi[k] - lo[k]) / cell_)));

  // Counting sort of (cell, face) pairs: each face goes into every cell its box overlaps.
  const std::size_t cells = static_cast<std::size_t>(dims_[0]) * dims_[1] * dims_[2];
  bucket_start_.assign(cells + 1, 0);
  auto for_cells = [&](std::size_t f, auto&& visit) {
    const auto& n = faces_[f].nodes;
    const Vec3 a = x[n[0]].cwiseMin(x[n[1]]).cwiseMin(x[n[2]]);
    const Vec3 b = x[n[0]].cwiseMax(x[n[1]]).cwiseMax(x[n[2]]);
    std::array<int, 3> i0, i1;
    cell_range(a, b, i0, i1);
    for (int k = i0[2]; k <= i1[2]; ++k)
      for (int j = i0[1]; j <= i1[1]; ++j)
        for (int i = i0[0]; i <= i1[0]; ++i)
          visit((static_cast<std::size_t>(k) * dims_[1] + j) * dims_[0] + i);
  };
  for (std::size_t f = 0; f < faces_.size(); ++f)
    for_cells(f, [&](std::size_t c) { ++bucket_start_[c + 1]; });
  for (std::size_t c = 0; c < cells; ++c) bucket_start_[c + 1] += bucket_start_[c];
  bucket_faces_.resize(bucket_start_[cells]);
  std::vector<std::uint32_t> fill(bucket_start_.begin(), bucket_start_.end() - 1);
  for (std::size_t f = 0; f < faces_.size(); ++f)
    for_cells(f, [&](std::size_t c) { bucket_faces_[fill[c]++] = static_cast<std::uint32_t>(f); });
}

void BoundarySurface::cell_range(const Vec3& lo, const Vec3& hi, std::array<int, 3>& a,
                                 std::array<int, 3>& b) const {
  for (int k = 0; k < 3; ++k) {
    a[k] = std::clamp(static_cast<int>(std::floor((lo[k] - origin_[k]) / cell_)), 0, dims_[k] - 1);
    b[k] = std::clamp(static_cast<int>(std::floor((hi[k] - origin_[k]) / cell_)), 0, dims_[k] - 1);
  }
}

void BoundarySurface::faces_near(const Vec3& p, double radius_m,
                                 std::vector<std::uint32_t>& out) const {
  if (faces_.empty()) return;
  const std::size_t first = out.size();
  std::array<int, 3> a, b;
  const Vec3 r = Vec3::Constant(radius_m);
  cell_range(p - r, p + r, a, b);
  const auto& x = *nodes_;
  for (int k = a[2]; k <= b[2]; ++k)
    for (int j = a[1]; j <= b[1]; ++j)
      for (int i = a[0]; i <= b[0]; ++i) {
        const std::size_t c = (static_cast<std::size_t>(k) * dims_[1] + j) * dims_[0] + i;
        for (std::uint32_t s = bucket_start_[c]; s < bucket_start_[c + 1]; ++s) {
          const auto& n = faces_[bucket_faces_[s]].nodes;
          const Vec3 lo = x[n[0]].cwiseMin(x[n[1]]).cwiseMin(x[n[2]]) - r;
          const Vec3 hi = x[n[0]].cwiseMax(x[n[1]]).cwiseMax(x[n[2]]) + r;
          if ((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all())
            out.push_back(bucket_faces_[s]);
        }
      }
  std::sort(out.begin() + first, out.end());
  out.erase(std::unique(out.begin() + first, out.end()), out.end());
}

int BoundarySurface::closest_face(const Vec3& p, double max_distance_m, Vec3* closest,
                                  double* distance_m) const {
  std::vector<std::uint32_t> near;
  faces_near(p, max_distance_m, near);
  const auto& x = *nodes_;
  int best = -1;
  double best_d2 = max_distance_m * max_distance_m;
  Vec3 best_q = p;
  for (std::uint32_t f : near) {
    const auto& n = faces_[f].nodes;
    const Vec3 q = closest_point_on_triangle(p, x[n[0]], x[n[1]], x[n[2]]);
    const double d2 = (q - p).squaredNorm();
    if (d2 <= best_d2) {
      best_d2 = d2;
      best = static_cast<int>(f);
      best_q = q;
    }
  }
  if (closest) *closest = best_q;
  if (distance_m) *distance_m = best >= 0 ? std::sqrt(best_d2) : max_distance_m;
  return best;
}

}  // namespace acdr
