// Contact patches to consistent nodal forces.
#include "engine/bone/surface_load.hpp"

#include <array>
#include <cmath>

namespace acdr {
namespace {

using Bary3 = std::array<double, 3>;

// Centroids of the 16 equal sub-triangles of a triangle whose edges are cut in four: the
// quadrature points of the patch integral.
std::array<Bary3, 16> subtriangle_centroids() {
  std::array<Bary3, 16> out{};
  constexpr int n = 4;
  int k = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; i + j < n; ++j) {
      const double u = (i + 1.0 / 3.0) / n, v = (j + 1.0 / 3.0) / n;
      out[k++] = {1.0 - u - v, u, v};
      if (i + j <= n - 2) {
        const double s = (i + 2.0 / 3.0) / n, t = (j + 2.0 / 3.0) / n;
        out[k++] = {1.0 - s - t, s, t};
      }
    }
  return out;
}

// Barycentric coordinates of q (in the plane of a, b, c).
Bary3 barycentric(const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 v0 = b - a, v1 = c - a, v2 = q - a;
  const double d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1);
  const double d20 = v2.dot(v0), d21 = v2.dot(v1);
  const double den = d00 * d11 - d01 * d01;
  if (den <= 0.0) return {1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0};
  const double v = (d11 * d20 - d01 * d21) / den, w = (d00 * d21 - d01 * d20) / den;
  return {1.0 - v - w, v, w};
}

// Shape functions of a face at barycentric l: 3 corners, or 6 (corners, edges 01, 12, 20).
int face_shape(TetOrder order, const Bary3& l, std::array<double, 6>& n) {
  if (order == TetOrder::kLinear) {
    n = {l[0], l[1], l[2], 0, 0, 0};
    return 3;
  }
  n = {l[0] * (2 * l[0] - 1), l[1] * (2 * l[1] - 1), l[2] * (2 * l[2] - 1),
       4 * l[0] * l[1],       4 * l[1] * l[2],       4 * l[2] * l[0]};
  return 6;
}

std::array<std::uint32_t, 6> face_nodes(const FeSpace& space, const BoundaryFace& f) {
  std::array<std::uint32_t, 6> out = {f.nodes[0], f.nodes[1], f.nodes[2], 0, 0, 0};
  if (space.order == TetOrder::kQuadratic) {
    out[3] = space.edge_node(f.nodes[0], f.nodes[1]);
    out[4] = space.edge_node(f.nodes[1], f.nodes[2]);
    out[5] = space.edge_node(f.nodes[2], f.nodes[0]);
  }
  return out;
}

}  // namespace

void add_face_traction(const FeSpace& space, const BoundarySurface& surface, std::size_t face,
                       const Vec3& traction, std::span<double> force) {
  const auto nodes = face_nodes(space, surface.faces()[face]);
  const Vec3 third = surface.face_area(face) / 3.0 * traction;
  // The integral of a quadratic triangle's corner functions is zero, of its edge functions 1/3.
  const int first = space.order == TetOrder::kLinear ? 0 : 3;
  for (int k = first; k < first + 3; ++k)
    for (int c = 0; c < 3; ++c) force[3 * nodes[k] + c] += third[c];
}

bool add_contact_load(const FeSpace& space, const BoundarySurface& surface,
                      const ContactLoad& contact, double max_snap_m, std::span<double> force,
                      std::vector<std::uint32_t>& scratch) {
  static const std::array<Bary3, 16> kPoints = subtriangle_centroids();
  const auto& x = space.nodes;
  Vec3 centre;
  const int nearest = surface.closest_face(contact.point_m, max_snap_m, &centre, nullptr);
  if (nearest < 0) return false;

  // First pass: the total weight, so the nodal forces sum to the contact force.
  const double a2 = contact.radius_m * contact.radius_m;
  scratch.clear();
  surface.faces_near(centre, contact.radius_m, scratch);
  auto for_each_point = [&](auto&& visit) {
    for (std::uint32_t f : scratch) {
      const auto& c = surface.faces()[f].nodes;
      const double w_area = surface.face_area(f) / static_cast<double>(kPoints.size());
      for (const Bary3& l : kPoints) {
        const Vec3 p = l[0] * x[c[0]] + l[1] * x[c[1]] + l[2] * x[c[2]];
        const double r2 = (p - centre).squaredNorm();
        if (r2 >= a2) continue;
        visit(f, l, w_area * std::sqrt(1.0 - r2 / a2));
      }
    }
  };
  double total = 0.0;
  for_each_point([&](std::uint32_t, const Bary3&, double w) { total += w; });

  std::array<double, 6> n;
  if (total <= 0.0) {
    // The patch falls between quadrature points: a point load on the nearest face.
    const BoundaryFace& f = surface.faces()[nearest];
    const Bary3 l = barycentric(centre, x[f.nodes[0]], x[f.nodes[1]], x[f.nodes[2]]);
    const auto nodes = face_nodes(space, f);
    const int count = face_shape(space.order, l, n);
    for (int k = 0; k < count; ++k)
      for (int c = 0; c < 3; ++c) force[3 * nodes[k] + c] += n[k] * contact.force_N[c];
    return true;
  }
  for_each_point([&](std::uint32_t f, const Bary3& l, double w) {
    const auto nodes = face_nodes(space, surface.faces()[f]);
    const int count = face_shape(space.order, l, n);
    const double share = w / total;
    for (int k = 0; k < count; ++k)
      for (int c = 0; c < 3; ++c) force[3 * nodes[k] + c] += share * n[k] * contact.force_N[c];
  });
  return true;
}

}  // namespace acdr
