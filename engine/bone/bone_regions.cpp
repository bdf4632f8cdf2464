// Region labels of a vertebra mesh from the body's box, the surface and each node's depth.
#include "engine/bone/bone_regions.hpp"

#include <algorithm>
#include <cmath>

namespace acdr {
namespace {

using Bary = std::array<double, 4>;

// Barycentric centroids of the 8^3 = 512 sub-tetrahedra of three rounds of midpoint
// subdivision. Each round splits a tetrahedron into four corner tetrahedra and four from the
// inner octahedron, all of an eighth of its volume, so the centroids sample volume evenly.
std::vector<Bary> subtet_centroids() {
  using Tet = std::array<Bary, 4>;
  std::vector<Tet> tets = {
      {Bary{1, 0, 0, 0}, Bary{0, 1, 0, 0}, Bary{0, 0, 1, 0}, Bary{0, 0, 0, 1}}};
  auto mid = [](const Bary& a, const Bary& b) {
    return Bary{0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2]), 0.5 * (a[3] + b[3])};
  };
  for (int round = 0; round < 3; ++round) {
    std::vector<Tet> next;
    for (const Tet& t : tets) {
      const Bary m01 = mid(t[0], t[1]), m02 = mid(t[0], t[2]), m03 = mid(t[0], t[3]);
      const Bary m12 = mid(t[1], t[2]), m13 = mid(t[1], t[3]), m23 = mid(t[2], t[3]);
      next.push_back({t[0], m01, m02, m03});
      next.push_back({m01, t[1], m12, m13});
      next.push_back({m02, m12, t[2], m23});
      next.push_back({m03, m13, m23, t[3]});
      // The octahedron, split along the diagonal m02-m13.
      next.push_back({m01, m02, m13, m12});
      next.push_back({m01, m02, m03, m13});
      next.push_back({m02, m13, m03, m23});
      next.push_back({m02, m12, m13, m23});
    }
    tets = std::move(next);
  }
  std::vector<Bary> out;
  for (const Tet& t : tets) {
    Bary c{};
    for (const Bary& p : t)
      for (int k = 0; k < 4; ++k) c[k] += 0.25 * p[k];
    out.push_back(c);
  }
  return out;
}

}  // namespace

const char* bone_region_name(BoneRegion region) {
  switch (region) {
    case BoneRegion::kCancellous:
      return "cancellous";
    case BoneRegion::kCortical:
      return "cortical";
    case BoneRegion::kEndplate:
      return "endplate";
    case BoneRegion::kPosterior:
      return "posterior";
  }
  return "?";
}

VertebraBodyFrame vertebra_body_frame(const SegmentParams& params, VertebraLevel level) {
  const VertebraParams& v = level == VertebraLevel::kC4 ? params.c4 : params.c5;
  VertebraBodyFrame b;
  b.center_m = vertebra_center(params, level);
  b.half_height_m = 0.5 * v.body_height_m;
  b.endplate_half_width_m = 0.5 * v.endplate_width_m;
  b.half_width_m = b.endplate_half_width_m + v.uncinate_thickness_m;
  b.front_z_m = 0.5 * v.body_depth_m;
  b.back_z_m = -0.5 * v.body_depth_m;
  return b;
}

double fraction_below(const std::array<double, 4>& d, double t) {
  static const std::vector<Bary> kSamples = subtet_centroids();
  if (std::max({d[0], d[1], d[2], d[3]}) < t) return 1.0;
  if (std::min({d[0], d[1], d[2], d[3]}) >= t) return 0.0;
  int below = 0;
  for (const Bary& s : kSamples)
    below += s[0] * d[0] + s[1] * d[1] + s[2] * d[2] + s[3] * d[3] < t ? 1 : 0;
  return static_cast<double>(below) / static_cast<double>(kSamples.size());
}

BoneRegionLabels classify_bone_regions(const TetMesh& mesh, const BoundarySurface& surface,
                                       const VertebraBodyFrame& body,
                                       const BoneShellParams& shell) {
  constexpr double kEdgeBand = 1.0e-3;  // the rounded rim of the body still counts as endplate
  const double kCos45 = std::sqrt(0.5);
  BoneRegionLabels out;
  const auto& faces = surface.faces();
  const auto& x = mesh.nodes;

  // Endplate faces: on the top or bottom of the body, inside the uncinate margins, facing
  // up or down.
  std::vector<std::uint8_t> endplate_face(faces.size(), 0);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto& n = faces[f].nodes;
    const Vec3 q = (x[n[0]] + x[n[1]] + x[n[2]]) / 3.0 - body.center_m;
    const double up = q.y() >= 0.0 ? 1.0 : -1.0;
    endplate_face[f] = std::abs(q.y()) >= body.half_height_m - kEdgeBand &&
                       std::abs(q.x()) <= body.endplate_half_width_m && q.z() >= body.back_z_m &&
                       q.z() <= body.front_z_m && up * surface.face_normal(f).y() >= kCos45;
  }

  // Depth of every node and the face it is nearest to.
  out.depth_cap_m =
      std::max(3.0 * surface.mean_edge_m(),
               4.0 * std::max(shell.cortical_thickness_m, shell.endplate_thickness_m));
  out.node_depth_m.assign(x.size(), out.depth_cap_m);
  std::vector<int> nearest(x.size(), -1);
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (std::uint32_t i : faces[f].nodes) {
      out.node_depth_m[i] = 0.0;
      if (nearest[i] < 0) nearest[i] = static_cast<int>(f);
    }
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (surface.on_surface()[i]) continue;
    double d = out.depth_cap_m;
    nearest[i] = surface.closest_face(x[i], out.depth_cap_m, nullptr, &d);
    out.node_depth_m[i] = d;
  }

  out.region.assign(mesh.tets.size(), static_cast<std::uint8_t>(BoneRegion::kCancellous));
  out.shell_fraction.assign(mesh.tets.size(), 0.0);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const Vec3 q = mesh.centroid(t) - body.center_m;
    if (q.z() < body.back_z_m || std::abs(q.x()) > body.half_width_m) {
      out.region[t] = static_cast<std::uint8_t>(BoneRegion::kPosterior);
      continue;
    }
    const auto& e = mesh.tets[t];
    std::array<double, 4> d;
    int shallow = 0;
    for (int k = 0; k < 4; ++k) {
      d[k] = out.node_depth_m[e[k]];
      if (d[k] < d[shallow]) shallow = k;
    }
    const int f = nearest[e[shallow]];
    const bool endplate = f >= 0 && endplate_face[f];
    const double fraction =
        fraction_below(d, endplate ? shell.endplate_thickness_m : shell.cortical_thickness_m);
    if (fraction <= 0.0) continue;
    out.region[t] =
        static_cast<std::uint8_t>(endplate ? BoneRegion::kEndplate : BoneRegion::kCortical);
    out.shell_fraction[t] = fraction;
  }
  return out;
}

}  // namespace acdr
