// Indexed triangle mesh: measures, welding and the closed-solid check.
#include "engine/geometry/triangle_mesh.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <unordered_map>

#include "engine/core/state_hash.hpp"

namespace acdr {

Vec3 TriangleMesh::triangle_normal(std::size_t t) const {
  const auto& tri = triangles[t];
  const Vec3& a = vertices[tri[0]];
  return (vertices[tri[1]] - a).cross(vertices[tri[2]] - a);
}

double TriangleMesh::signed_volume() const {
  // Sum of signed tetrahedra (origin, a, b, c): V = 1/6 sum a . (b x c) (divergence theorem).
  // Taken about the first vertex rather than the origin to limit cancellation far from it.
  if (vertices.empty()) return 0.0;
  const Vec3 o = vertices[0];
  double six_v = 0.0;
  for (const auto& tri : triangles) {
    const Vec3 a = vertices[tri[0]] - o, b = vertices[tri[1]] - o, c = vertices[tri[2]] - o;
    six_v += a.dot(b.cross(c));
  }
  return six_v / 6.0;
}

double TriangleMesh::area() const {
  double twice = 0.0;
  for (std::size_t t = 0; t < triangles.size(); ++t) twice += triangle_normal(t).norm();
  return 0.5 * twice;
}

void TriangleMesh::bounds(Vec3* min_m, Vec3* max_m) const {
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
  if (!vertices.empty()) {
    lo = hi = vertices[0];
    for (const Vec3& v : vertices) {
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
  }
  if (min_m) *min_m = lo;
  if (max_m) *max_m = hi;
}

void TriangleMesh::append(const TriangleMesh& other) {
  const auto base = static_cast<std::uint32_t>(vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  triangles.reserve(triangles.size() + other.triangles.size());
  for (const auto& t : other.triangles) triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

void TriangleMesh::transform(const Pose& pose) {
  for (Vec3& v : vertices) v = pose.apply(v);
}

namespace {

struct BitsHash {
  std::size_t operator()(const std::array<std::uint64_t, 3>& k) const {
    return static_cast<std::size_t>(fnv1a(k.data(), sizeof(k)));
  }
};

std::array<std::uint64_t, 3> bits_of(const Vec3& v) {
  std::array<std::uint64_t, 3> k;
  for (int i = 0; i < 3; ++i) {
    // +0.0 and -0.0 are the same point.
    const double x = v[i] == 0.0 ? 0.0 : v[i];
    std::memcpy(&k[i], &x, sizeof(double));
  }
  return k;
}

}  // namespace

std::size_t TriangleMesh::weld_exact() {
  // The map is only looked up, never iterated, so its order cannot leak into the result.
  std::unordered_map<std::array<std::uint64_t, 3>, std::uint32_t, BitsHash> index;
  index.reserve(vertices.size());
  std::vector<Vec3> welded;
  welded.reserve(vertices.size());
  for (auto& tri : triangles) {
    for (auto& i : tri) {
      const Vec3 v = vertices[i];
      auto [it, inserted] = index.try_emplace(bits_of(v), static_cast<std::uint32_t>(welded.size()));
      if (inserted) welded.push_back(v);
      i = it->second;
    }
  }
  const std::size_t removed = vertices.size() - welded.size();
  vertices = std::move(welded);
  return removed;
}

std::uint64_t TriangleMesh::content_hash() const {
  std::uint64_t h = kFnvOffset;
  const std::uint64_t nv = vertices.size(), nt = triangles.size();
  h = fnv1a(&nv, sizeof nv, h);
  h = fnv1a(&nt, sizeof nt, h);
  if (!vertices.empty()) h = fnv1a(vertices.data(), vertices.size() * sizeof(Vec3), h);
  if (!triangles.empty()) h = fnv1a(triangles.data(), triangles.size() * sizeof(triangles[0]), h);
  return h;
}

namespace {
constexpr char kMeshMagic[8] = {'A', 'C', 'D', 'R', 'M', 'S', 'H', '1'};
}  // namespace

std::string TriangleMesh::serialize() const {
  const std::uint64_t nv = vertices.size(), nt = triangles.size();
  std::string out(sizeof kMeshMagic + 16 + nv * sizeof(Vec3) + nt * sizeof(triangles[0]), '\0');
  char* at = out.data();
  std::memcpy(at, kMeshMagic, sizeof kMeshMagic);
  std::memcpy(at + 8, &nv, 8);
  std::memcpy(at + 16, &nt, 8);
  if (nv) std::memcpy(at + 24, vertices.data(), nv * sizeof(Vec3));
  if (nt) std::memcpy(at + 24 + nv * sizeof(Vec3), triangles.data(), nt * sizeof(triangles[0]));
  return out;
}

std::optional<TriangleMesh> TriangleMesh::deserialize(std::string_view bytes, std::string* error) {
  auto fail = [&](const std::string& why) -> std::optional<TriangleMesh> {
    if (error) *error = why;
    return std::nullopt;
  };
  if (bytes.size() < 24 || std::memcmp(bytes.data(), kMeshMagic, 8) != 0) return fail("not a mesh cache file");
  std::uint64_t nv = 0, nt = 0;
  std::memcpy(&nv, bytes.data() + 8, 8);
  std::memcpy(&nt, bytes.data() + 16, 8);
  if (nv > (1ull << 32) || nt > (1ull << 32) ||
      bytes.size() != 24 + nv * sizeof(Vec3) + nt * sizeof(std::array<std::uint32_t, 3>)) {
    return fail("size does not match its counts (truncated?)");
  }
  TriangleMesh m;
  m.vertices.resize(nv);
  m.triangles.resize(nt);
  if (nv) std::memcpy(m.vertices.data(), bytes.data() + 24, nv * sizeof(Vec3));
  if (nt) std::memcpy(m.triangles.data(), bytes.data() + 24 + nv * sizeof(Vec3), nt * sizeof(m.triangles[0]));
  for (const auto& t : m.triangles) {
    if (t[0] >= nv || t[1] >= nv || t[2] >= nv) return fail("a triangle refers to a missing vertex");
  }
  return m;
}

std::string format_point_mm(const Vec3& p) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.2f, %.2f, %.2f mm)", p.x() * 1e3, p.y() * 1e3, p.z() * 1e3);
  return text;
}

MeshCheck check_closed_mesh(const TriangleMesh& mesh, double min_area_m2) {
  MeshCheck out;
  const std::size_t nv = mesh.vertices.size();
  std::string first_bad_index, first_degenerate;

  // Directed edges of the valid triangles, keyed by their undirected vertex pair.
  struct Edge {
    std::uint32_t lo, hi;
    bool forward;  // runs lo -> hi
  };
  std::vector<Edge> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    if (tri[0] >= nv || tri[1] >= nv || tri[2] >= nv) {
      if (out.bad_indices++ == 0) {
        first_bad_index = "triangle " + std::to_string(t) + " refers to vertex " +
                          std::to_string(std::max({tri[0], tri[1], tri[2]})) + " of " +
                          std::to_string(nv);
      }
      continue;
    }
    const bool repeated = tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2];
    if (repeated || 0.5 * mesh.triangle_normal(t).norm() < min_area_m2) {
      if (out.degenerate_triangles++ == 0) {
        first_degenerate = "triangle " + std::to_string(t) + " at vertex " + std::to_string(tri[0]) +
                           " " + format_point_mm(mesh.vertices[tri[0]]);
      }
      if (repeated) continue;  // its edges would be self-loops
    }
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = tri[k], b = tri[(k + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), a < b});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) {
    return x.lo != y.lo ? x.lo < y.lo : x.hi != y.hi ? x.hi < y.hi : x.forward < y.forward;
  });

  // Each undirected edge must appear exactly twice, once in each direction.
  std::uint32_t open_at = 0, nonmanifold_at = 0, flipped_at = 0;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) ++j;
    const std::size_t uses = j - i;
    if (uses == 1) {
      if (out.open_edges++ == 0) open_at = edges[i].lo;
    } else if (uses > 2) {
      if (out.non_manifold_edges++ == 0) nonmanifold_at = edges[i].lo;
    } else if (edges[i].forward == edges[i + 1].forward) {
      if (out.flipped_edges++ == 0) flipped_at = edges[i].lo;
    }
    i = j;
  }
  out.volume_m3 = mesh.signed_volume();

  auto add = [&](const std::string& sentence) {
    if (!out.error.empty()) out.error += "; ";
    out.error += sentence;
  };
  auto at_vertex = [&](std::uint32_t v) {
    return "first at vertex " + std::to_string(v) + " " + format_point_mm(mesh.vertices[v]);
  };
  if (mesh.triangles.empty()) add("no triangles (expected a closed surface)");
  if (out.bad_indices) {
    add(std::to_string(out.bad_indices) + " triangles with a vertex index out of range, first " +
        first_bad_index);
  }
  if (out.open_edges) {
    add(std::to_string(out.open_edges) + " open edges (holes; expected every edge shared by two "
        "triangles), " + at_vertex(open_at));
  }
  if (out.non_manifold_edges) {
    add(std::to_string(out.non_manifold_edges) + " non-manifold edges (shared by more than two "
        "triangles), " + at_vertex(nonmanifold_at));
  }
  if (out.flipped_edges) {
    add(std::to_string(out.flipped_edges) + " edges where neighbouring triangles disagree in "
        "orientation (expected consistent winding), " + at_vertex(flipped_at));
  }
  if (out.degenerate_triangles) {
    add(std::to_string(out.degenerate_triangles) + " degenerate triangles (repeated vertex or "
        "zero area), first " + first_degenerate);
  }
  // Orientation is only meaningful once the surface is closed and consistently wound.
  if (out.error.empty() && !(out.volume_m3 > 0.0)) {
    char vol[64];
    std::snprintf(vol, sizeof vol, "%.4g mm^3", out.volume_m3 * 1e9);
    add(std::string("triangles face inward (signed volume ") + vol +
        ", expected > 0: counter-clockwise seen from outside)");
  }
  out.ok = out.error.empty();
  return out;
}

}  // namespace acdr
