// A tetrahedral mesh of a solid (SI metres): nodes, four-node tetrahedra with a region label
// each, and the quality figures a finite-element mesh is judged by (minimum dihedral angle,
// aspect ratio). Meshers produce it (tet_mesher.hpp), the bone model labels its regions
// (bone_regions.hpp), the elasticity solver reads it (elastic_model.hpp), and the disk cache
// stores it in the byte form below.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/types.hpp"

namespace acdr {

/// Tetrahedra are positively oriented: (b - a) x (c - a) . (d - a) > 0.
struct TetMesh {
  std::vector<Vec3> nodes;                         ///< N positions, m
  std::vector<std::array<std::uint32_t, 4>> tets;  ///< T corner index quadruples
  std::vector<std::uint8_t> region;                ///< T labels (meaning set by the user)

  std::size_t node_count() const { return nodes.size(); }
  std::size_t tet_count() const { return tets.size(); }
  /// Signed volume of tetrahedron t (m^3), positive when oriented as above.
  double tet_volume(std::size_t t) const;
  /// Sum of |tet volumes| (m^3).
  double volume() const;
  /// Centroid of tetrahedron t (m).
  Vec3 centroid(std::size_t t) const;

  /// Raw bytes for the disk cache, and back; `deserialize` checks sizes and indices.
  std::string serialize() const;
  static std::optional<TetMesh> deserialize(std::string_view bytes, std::string* error);
};

/// A boundary face: three corner nodes, counter-clockwise seen from outside, and its tet.
struct BoundaryFace {
  std::array<std::uint32_t, 3> nodes{};
  std::uint32_t tet = 0;
};

/// The faces used by exactly one tetrahedron, outward oriented, in a deterministic order
/// (sorted by tetrahedron, then local face).
std::vector<BoundaryFace> boundary_faces(const TetMesh& mesh);

/// Shape figures of one tetrahedron.
struct TetShape {
  double min_dihedral_deg = 0.0;  ///< smallest angle between two faces (70.5 for a regular tet)
  double max_dihedral_deg = 0.0;
  /// Circumradius over three times the inradius: 1 for a regular tetrahedron, large for a
  /// sliver or a needle (the radius-ratio measure, inverted).
  double aspect_ratio = 0.0;
};
TetShape tet_shape(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Quality of a whole mesh.
struct TetQuality {
  std::size_t tets = 0;
  std::size_t inverted = 0;       ///< tets with volume <= 0
  double min_dihedral_deg = 0.0;  ///< worst tet
  double max_dihedral_deg = 0.0;
  double dihedral_p01_deg = 0.0;  ///< 1st percentile of the per-tet minimum dihedral
  double max_aspect_ratio = 0.0;
  double mean_aspect_ratio = 0.0;
  double volume_m3 = 0.0;
};
TetQuality tet_quality(const TetMesh& mesh);

/// Thresholds a mesh must meet before the solver uses it. Defaults: a tet under 5 degrees or
/// with an aspect ratio over 30 spoils the stiffness conditioning and the stress around it.
struct TetQualityLimits {
  double min_dihedral_deg = 5.0;
  double max_aspect_ratio = 30.0;
};

/// "" when `q` meets `limits`, else what fails, e.g. "minimum dihedral angle 1.2 deg < 5 deg".
std::string check_tet_quality(const TetQuality& q, const TetQualityLimits& limits);

}  // namespace acdr
