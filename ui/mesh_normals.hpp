// Vertex normals for meshes that come without them (OBJ/STL bone, scene builders): smooth
// across gentle edges, split across sharp ones, so one routine serves boxes and vertebrae.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace acdr {

/// A mesh ready for drawing: one normal per vertex, triangles indexing both.
struct NormalMesh {
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;  ///< unit, one per position
  std::vector<std::uint32_t> indices;    ///< triangles
};

/// Area-weighted vertex normals that average only over the faces around a vertex whose normals
/// are within `crease_angle_deg` of each other (typical 35); a vertex on a sharper edge is split
/// into one copy per side. Triangles with an index out of range or zero area are dropped (their
/// count is returned in `dropped` when given).
NormalMesh compute_crease_normals(const std::vector<Eigen::Vector3f>& vertices,
                                  const std::vector<std::uint32_t>& indices,
                                  float crease_angle_deg = 35.0f, int* dropped = nullptr);

}  // namespace acdr
