// An indexed triangle mesh in SI metres (bone surfaces), and the checks a mesh must pass before
// the engine uses it as a solid: closed and watertight (every edge shared by exactly two
// triangles that run it in opposite directions), outward orientation (positive signed volume),
// no degenerate triangles. A failed check names what is wrong and where, in millimetres.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/types.hpp"

namespace acdr {

/// Triangles are counter-clockwise seen from outside (right-hand normal points outward).
struct TriangleMesh {
  std::vector<Vec3> vertices;                            ///< V positions, m
  std::vector<std::array<std::uint32_t, 3>> triangles;   ///< T vertex index triples

  std::size_t vertex_count() const { return vertices.size(); }
  std::size_t triangle_count() const { return triangles.size(); }
  /// Unnormalised normal (b - a) x (c - a) of triangle t; its length is twice the area (m^2).
  Vec3 triangle_normal(std::size_t t) const;
  /// Signed enclosed volume by the divergence theorem (m^3): positive for a closed mesh whose
  /// triangles face outward.
  double signed_volume() const;
  /// Surface area (m^2).
  double area() const;
  /// Axis-aligned bounds of the vertices; both zero for an empty mesh.
  void bounds(Vec3* min_m, Vec3* max_m) const;
  /// Appends another mesh (indices shifted), e.g. two vertebrae into one scene mesh.
  void append(const TriangleMesh& other);
  /// Moves every vertex by a rigid pose: p -> pose.apply(p).
  void transform(const Pose& pose);
  /// Merges vertices with bit-identical coordinates and drops unused ones; vertices are
  /// renumbered in order of first use by the triangles, so two files listing the same
  /// triangles in the same order give the same mesh. Returns the number of vertices removed.
  std::size_t weld_exact();
  /// The mesh's bytes (vertex coordinates then indices), hashed with FNV-1a 64: a content key
  /// for caches (signed distance grids).
  std::uint64_t content_hash() const;

  /// Raw bytes (counts, vertices, triangles) for a disk cache, and back; `deserialize` checks
  /// sizes and indices and says what is wrong.
  std::string serialize() const;
  static std::optional<TriangleMesh> deserialize(std::string_view bytes, std::string* error);
};

/// What `check_closed_mesh` found. Counts are of undirected edges / triangles.
struct MeshCheck {
  bool ok = false;
  std::size_t open_edges = 0;         ///< edges used by one triangle only (holes)
  std::size_t non_manifold_edges = 0; ///< edges used by more than two triangles
  std::size_t flipped_edges = 0;      ///< edges two triangles run in the same direction
  std::size_t degenerate_triangles = 0;  ///< repeated index or (near) zero area
  std::size_t bad_indices = 0;        ///< triangles referring to a vertex that does not exist
  double volume_m3 = 0.0;             ///< signed volume
  /// Empty when ok; else one sentence per problem, e.g.
  /// "12 open edges (holes), first at vertex 345 (1.20, -3.40, 5.00 mm)".
  std::string error;
};

/// Checks that `mesh` bounds a solid. A triangle is degenerate when it repeats a vertex or its
/// area is below `min_area_m2` (default 1e-16 m^2 = 1e-10 mm^2, far below any meshing scale).
MeshCheck check_closed_mesh(const TriangleMesh& mesh, double min_area_m2 = 1e-16);

/// "(x, y, z mm)" with two decimals, for messages.
std::string format_point_mm(const Vec3& p_m);

}  // namespace acdr
