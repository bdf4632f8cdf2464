// Tetrahedral mesh: volumes, boundary faces, shape quality and the cache byte form.
#include "engine/bone/tet_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numbers>

namespace acdr {
namespace {

constexpr char kTetMagic[8] = {'A', 'C', 'D', 'R', 'T', 'E', 'T', '1'};

// Local faces of a tetrahedron, each opposite the corner of the same index, ordered so the
// right-hand normal points away from that corner when the tet is positively oriented.
constexpr int kFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

}  // namespace

double TetMesh::tet_volume(std::size_t t) const {
  const auto& e = tets[t];
  const Vec3& a = nodes[e[0]];
  return (nodes[e[1]] - a).cross(nodes[e[2]] - a).dot(nodes[e[3]] - a) / 6.0;
}

double TetMesh::volume() const {
  double v = 0.0;
  for (std::size_t t = 0; t < tets.size(); ++t) v += std::abs(tet_volume(t));
  return v;
}

Vec3 TetMesh::centroid(std::size_t t) const {
  const auto& e = tets[t];
  return 0.25 * (nodes[e[0]] + nodes[e[1]] + nodes[e[2]] + nodes[e[3]]);
}

std::string TetMesh::serialize() const {
  const std::uint64_t nn = nodes.size(), nt = tets.size();
  const std::size_t bytes_nodes = nn * sizeof(Vec3), bytes_tets = nt * sizeof(tets[0]);
  std::string out(24 + bytes_nodes + bytes_tets + nt, '\0');
  char* at = out.data();
  std::memcpy(at, kTetMagic, 8);
  std::memcpy(at + 8, &nn, 8);
  std::memcpy(at + 16, &nt, 8);
  if (nn) std::memcpy(at + 24, nodes.data(), bytes_nodes);
  if (nt) std::memcpy(at + 24 + bytes_nodes, tets.data(), bytes_tets);
  // A mesh without labels stores zeros.
  if (nt && region.size() == nt) std::memcpy(at + 24 + bytes_nodes + bytes_tets, region.data(), nt);
  return out;
}

std::optional<TetMesh> TetMesh::deserialize(std::string_view bytes, std::string* error) {
  auto fail = [&](const std::string& why) -> std::optional<TetMesh> {
    if (error) *error = why;
    return std::nullopt;
  };
  if (bytes.size() < 24 || std::memcmp(bytes.data(), kTetMagic, 8) != 0)
    return fail("not a tetrahedral mesh cache file");
  std::uint64_t nn = 0, nt = 0;
  std::memcpy(&nn, bytes.data() + 8, 8);
  std::memcpy(&nt, bytes.data() + 16, 8);
  if (nn > (1ull << 32) || nt > (1ull << 32) ||
      bytes.size() != 24 + nn * sizeof(Vec3) + nt * sizeof(std::array<std::uint32_t, 4>) + nt)
    return fail("size does not match its counts (truncated?)");
  TetMesh m;
  m.nodes.resize(nn);
  m.tets.resize(nt);
  m.region.resize(nt);
  const std::size_t bytes_nodes = nn * sizeof(Vec3), bytes_tets = nt * sizeof(m.tets[0]);
  if (nn) std::memcpy(static_cast<void*>(m.nodes.data()), bytes.data() + 24, bytes_nodes);
  if (nt) std::memcpy(m.tets.data(), bytes.data() + 24 + bytes_nodes, bytes_tets);
  if (nt) std::memcpy(m.region.data(), bytes.data() + 24 + bytes_nodes + bytes_tets, nt);
  for (const auto& t : m.tets)
    for (std::uint32_t i : t)
      if (i >= nn) return fail("a tetrahedron refers to a missing node");
  return m;
}

std::vector<BoundaryFace> boundary_faces(const TetMesh& mesh) {
  // Every face keyed by its sorted corners; a key seen once is on the boundary.
  struct Face {
    std::array<std::uint32_t, 3> key;
    std::uint32_t tet;
    std::uint8_t local;
  };
  std::vector<Face> faces;
  faces.reserve(4 * mesh.tets.size());
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    for (std::uint8_t f = 0; f < 4; ++f) {
      std::array<std::uint32_t, 3> k = {mesh.tets[t][kFaces[f][0]], mesh.tets[t][kFaces[f][1]],
                                        mesh.tets[t][kFaces[f][2]]};
      std::sort(k.begin(), k.end());
      faces.push_back({k, static_cast<std::uint32_t>(t), f});
    }
  }
  std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) {
    return a.key != b.key ? a.key < b.key : a.tet < b.tet;
  });
  std::vector<std::pair<std::uint32_t, std::uint8_t>> once;
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    if (j - i == 1) once.emplace_back(faces[i].tet, faces[i].local);
    i = j;
  }
  std::sort(once.begin(), once.end());
  std::vector<BoundaryFace> out;
  out.reserve(once.size());
  for (const auto& [t, f] : once) {
    const auto& e = mesh.tets[t];
    BoundaryFace b;
    b.nodes = {e[kFaces[f][0]], e[kFaces[f][1]], e[kFaces[f][2]]};
    b.tet = t;
    // Positive tets have outward local faces; a negative one turns them inward.
    if (mesh.tet_volume(t) < 0.0) std::swap(b.nodes[1], b.nodes[2]);
    out.push_back(b);
  }
  return out;
}

TetShape tet_shape(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 p[4] = {a, b, c, d};
  const double volume = (b - a).cross(c - a).dot(d - a) / 6.0;
  // Outward unit normals (flipped when the tet is inverted) and the total area.
  Vec3 n[4];
  double area = 0.0;
  for (int i = 0; i < 4; ++i) {
    n[i] = (p[kFaces[i][1]] - p[kFaces[i][0]]).cross(p[kFaces[i][2]] - p[kFaces[i][0]]);
    area += 0.5 * n[i].norm();
    if (n[i].dot(p[kFaces[i][0]] - p[i]) < 0.0) n[i] = -n[i];
    const double len = n[i].norm();
    if (len > 0.0) n[i] /= len;
  }
  TetShape s;
  s.min_dihedral_deg = 180.0;
  for (int i = 0; i < 4; ++i) {
    for (int j = i + 1; j < 4; ++j) {
      // The interior angle between two faces is pi minus the angle between their normals.
      const double cosine = std::clamp(n[i].dot(n[j]), -1.0, 1.0);
      const double angle = 180.0 - std::acos(cosine) * 180.0 / std::numbers::pi;
      s.min_dihedral_deg = std::min(s.min_dihedral_deg, angle);
      s.max_dihedral_deg = std::max(s.max_dihedral_deg, angle);
    }
  }
  // Inradius 3V/A; circumcentre c solves 2 (p_i - a) . c = |p_i - a|^2.
  const double inradius = 3.0 * std::abs(volume) / area;
  Eigen::Matrix3d m;
  m.row(0) = b - a;
  m.row(1) = c - a;
  m.row(2) = d - a;
  const Vec3 rhs(m.row(0).squaredNorm(), m.row(1).squaredNorm(), m.row(2).squaredNorm());
  const double det = m.determinant();
  const double circumradius =
      det != 0.0 ? (m.inverse() * (0.5 * rhs)).norm() : std::numeric_limits<double>::infinity();
  s.aspect_ratio =
      inradius > 0.0 ? circumradius / (3.0 * inradius) : std::numeric_limits<double>::infinity();
  if (volume <= 0.0) s.min_dihedral_deg = 0.0;
  return s;
}

TetQuality tet_quality(const TetMesh& mesh) {
  TetQuality q;
  q.tets = mesh.tets.size();
  if (mesh.tets.empty()) return q;
  std::vector<double> mins;
  mins.reserve(mesh.tets.size());
  q.min_dihedral_deg = 180.0;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& e = mesh.tets[t];
    const double v = mesh.tet_volume(t);
    if (v <= 0.0) ++q.inverted;
    q.volume_m3 += std::abs(v);
    const TetShape s =
        tet_shape(mesh.nodes[e[0]], mesh.nodes[e[1]], mesh.nodes[e[2]], mesh.nodes[e[3]]);
    q.min_dihedral_deg = std::min(q.min_dihedral_deg, s.min_dihedral_deg);
    q.max_dihedral_deg = std::max(q.max_dihedral_deg, s.max_dihedral_deg);
    q.max_aspect_ratio = std::max(q.max_aspect_ratio, s.aspect_ratio);
    q.mean_aspect_ratio += s.aspect_ratio;
    mins.push_back(s.min_dihedral_deg);
  }
  q.mean_aspect_ratio /= static_cast<double>(mesh.tets.size());
  std::nth_element(mins.begin(), mins.begin() + mins.size() / 100, mins.end());
  q.dihedral_p01_deg = mins[mins.size() / 100];
  return q;
}

std::string check_tet_quality(const TetQuality& q, const TetQualityLimits& limits) {
  char text[160];
  std::string out;
  if (q.tets == 0) return "the mesh has no tetrahedra";
  if (q.inverted > 0) {
    std::snprintf(text, sizeof text, "%zu inverted or flat tetrahedra; ", q.inverted);
    out += text;
  }
  if (q.min_dihedral_deg < limits.min_dihedral_deg) {
    std::snprintf(text, sizeof text, "minimum dihedral angle %.2f deg < %.2f deg; ",
                  q.min_dihedral_deg, limits.min_dihedral_deg);
    out += text;
  }
  if (!(q.max_aspect_ratio <= limits.max_aspect_ratio)) {
    std::snprintf(text, sizeof text, "aspect ratio %.1f > %.1f; ", q.max_aspect_ratio,
                  limits.max_aspect_ratio);
    out += text;
  }
  if (!out.empty()) out.resize(out.size() - 2);
  return out;
}

}  // namespace acdr
