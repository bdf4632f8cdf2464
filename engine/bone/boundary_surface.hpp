// The outer surface of a tetrahedral mesh (its boundary faces) with a uniform grid of buckets
// for nearby-face queries: the closest surface point to a contact, the faces under a load
// patch, each node's depth below the surface. Immutable after construction, so any number of
// threads may query it.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "engine/bone/tet_mesh.hpp"

namespace acdr {

class BoundarySurface {
 public:
  /// Extracts the boundary faces of `mesh` and buckets them (cells about two mean face edges).
  explicit BoundarySurface(const TetMesh& mesh);

  const std::vector<BoundaryFace>& faces() const { return faces_; }
  /// Area (m^2) and outward unit normal of face f.
  double face_area(std::size_t f) const { return area_[f]; }
  const Vec3& face_normal(std::size_t f) const { return normal_[f]; }
  /// Mean edge length of the boundary faces (m).
  double mean_edge_m() const { return mean_edge_; }
  /// True for the nodes that lie on the surface (size: the mesh's node count).
  const std::vector<std::uint8_t>& on_surface() const { return on_surface_; }

  /// The face closest to `p` among those within `max_distance_m`, or -1; fills the closest
  /// point and its distance.
  int closest_face(const Vec3& p, double max_distance_m, Vec3* closest, double* distance_m) const;
  /// Appends to `out` every face whose bounding box comes within `radius_m` of `p` (each once,
  /// ascending).
  void faces_near(const Vec3& p, double radius_m, std::vector<std::uint32_t>& out) const;

 private:
  void cell_range(const Vec3& lo, const Vec3& hi, std::array<int, 3>& a,
                  std::array<int, 3>& b) const;

  const std::vector<Vec3>* nodes_;  // the mesh's nodes (the mesh outlives this object)
  std::vector<BoundaryFace> faces_;
  std::vector<double> area_;
  std::vector<Vec3> normal_;
  std::vector<std::uint8_t> on_surface_;
  double mean_edge_ = 0.0;
  // Buckets: cell c holds faces bucket_faces_[bucket_start_[c] .. bucket_start_[c + 1]).
  Vec3 origin_ = Vec3::Zero();
  double cell_ = 1.0;
  std::array<int, 3> dims_{1, 1, 1};
  std::vector<std::uint32_t> bucket_start_;
  std::vector<std::uint32_t> bucket_faces_;
};

}  // namespace acdr
