// Volume meshing of a closed bone surface into quality tetrahedra, with CGAL's Mesh_3 (Debian's
// libcgal-dev): Delaunay refinement against the surface (a polyhedral domain, so a generated
// vertebra and an imported OBJ/STL mesh go the same way), then sliver perturbation and
// exudation. The surface is re-sampled at the target size, so the input triangle count does
// not set the element count. Chosen over Gmsh and TetGen by measurement (docs/bone-fem.md).
#pragma once

#include <optional>
#include <string>

#include "engine/bone/tet_mesh.hpp"
#include "engine/geometry/triangle_mesh.hpp"

namespace acdr {

/// What the mesher aims at (SI). Typical vertebra: size 1.5 mm gives ~17 000 tetrahedra.
struct TetMeshingParams {
  /// Target edge length of the surface triangles and circumradius bound of the tetrahedra (m).
  double size_m = 1.5e-3;
  /// Largest distance between a surface triangle's circumcentre and the input surface, as a
  /// fraction of size_m: how closely the re-sampled surface follows curved bone (0.15 mm at
  /// 1.5 mm). A fixed small distance with large elements grades the mesh steeply from the
  /// surface inward and the sliver optimisation then takes ten times longer (measured).
  double surface_distance_ratio = 0.1;
  /// Smallest angle of a surface triangle (deg, at most 30 for Delaunay refinement to end).
  double facet_angle_deg = 25.0;
  /// Circumradius over shortest edge of a tetrahedron (at least 2 for refinement to end).
  double radius_edge_ratio = 3.0;
  /// Sliver optimisation: perturbation and exudation try to lift every dihedral angle above
  /// this bound (deg). 10 degrees is what they reach on vertebrae (docs/bone-fem.md).
  double sliver_bound_deg = 10.0;
  /// A mesh that misses these after optimisation is refused.
  TetQualityLimits limits;
};

/// The mesh, or why there is none.
struct TetMeshingResult {
  std::optional<TetMesh> mesh;  ///< regions all 0
  TetQuality quality;
  double seconds = 0.0;  ///< wall time of checks, refinement and optimisation
  /// Empty on success; otherwise what is wrong with the surface or the mesh, e.g.
  /// "not a closed surface: 3 open edges (holes), first at vertex 2 (1.00, 0.00, 0.00 mm)" or
  /// "the surface intersects itself (12 pairs of triangles), first near (...)".
  std::string error;
};

/// Meshes the solid bounded by `surface` (closed, outward, non-degenerate, not
/// self-intersecting; checked first). Never throws: a failure is a result with an error.
TetMeshingResult mesh_closed_surface(const TriangleMesh& surface, const TetMeshingParams& params);

/// "" when the parameters can be meshed with, else "size_m: got -1 mm, expected > 0".
std::string validate_tet_meshing_params(const TetMeshingParams& params);

}  // namespace acdr
