// The regions of a vertebra's tetrahedral mesh: cortical shell, cancellous core, bony endplates
// and posterior elements, found from geometry alone so a generated and an imported vertebra are
// labelled the same way:
//  - posterior elements (pedicles, laminae, lateral masses, transverse and spinous processes):
//    tetrahedra whose centroid lies behind the posterior wall of the body or lateral to it;
//  - in the body, tetrahedra reaching into the outer shell (depth below the surface less than
//    the shell thickness) are shell tetrahedra: endplate where the nearest surface is the top or
//    bottom of the body (inside the uncinate margins, facing up or down), cortical elsewhere;
//  - the rest of the body is cancellous.
// The shell (0.4-0.5 mm) is thinner than any affordable element, so each shell tetrahedron also
// carries the fraction of its volume that lies within the shell thickness; the material model
// mixes the shell and cancellous stiffness by that fraction (bone_material.hpp).
#pragma once

#include <cstdint>
#include <vector>

#include "engine/anatomy/vertebra_generator.hpp"
#include "engine/bone/boundary_surface.hpp"
#include "engine/bone/tet_mesh.hpp"

namespace acdr {

enum class BoneRegion : std::uint8_t {
  kCancellous = 0,
  kCortical = 1,
  kEndplate = 2,
  kPosterior = 3
};
inline constexpr int kBoneRegionCount = 4;
/// "cancellous", "cortical", "endplate", "posterior".
const char* bone_region_name(BoneRegion region);

/// Where the vertebral body is (segment frame, SI): the box the regions are told apart by.
struct VertebraBodyFrame {
  Vec3 center_m = Vec3::Zero();        ///< centre of the body
  double half_height_m = 0.0;          ///< endplates at center.y +- this
  double half_width_m = 0.0;           ///< lateral body wall (with the uncinate processes), |x|
  double endplate_half_width_m = 0.0;  ///< medial uncinate margins, |x|
  double front_z_m = 0.0;              ///< anterior wall, relative to the centre
  double back_z_m = 0.0;               ///< posterior wall, relative to the centre (negative)
};

/// The body frame of a vertebra from the segment's morphometry (also used with loaded meshes,
/// which are in the same frame, docs/anatomy.md).
VertebraBodyFrame vertebra_body_frame(const SegmentParams& params, VertebraLevel level);

/// Thicknesses of the thin layers (SI).
struct BoneShellParams {
  double cortical_thickness_m = 0.4e-3;  ///< cortical shell of the body
  double endplate_thickness_m = 0.5e-3;  ///< bony endplate
};

/// Per-tetrahedron labels and shell fractions, per-node depths.
struct BoneRegionLabels {
  std::vector<std::uint8_t> region;    ///< T, BoneRegion
  std::vector<double> shell_fraction;  ///< T, volume fraction within the shell (0 off the shell)
  std::vector<double> node_depth_m;    ///< N, distance to the surface (capped, see below)
  double depth_cap_m = 0.0;            ///< depths beyond this are stored as this
};

/// Labels every tetrahedron of a vertebra mesh.
BoneRegionLabels classify_bone_regions(const TetMesh& mesh, const BoundarySurface& surface,
                                       const VertebraBodyFrame& body, const BoneShellParams& shell);

/// Fraction of a tetrahedron's volume where a linear field with corner values `d` is below `t`
/// (exact to 1/512: the field is sampled at the centroids of 512 equal sub-tetrahedra).
double fraction_below(const std::array<double, 4>& d, double t);

}  // namespace acdr
