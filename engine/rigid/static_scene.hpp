// The static solids of a practice scene, ground plane and the seed's open box, and the
// colliders the particles see for them.
#pragma once

#include <vector>

#include "engine/core/types.hpp"
#include "engine/geometry/collider.hpp"

namespace acdr {

struct GroundConfig {
  bool enabled = false;
  double height_m = 0.0;  ///< the plane z = height_m, normal +z
};

/// The seed's static open box: a floor and four side walls (five wall actors), open at +z.
struct OpenBoxConfig {
  bool enabled = false;
  Vec3 inner_min_m = Vec3::Zero();  ///< inner cavity, axis-aligned, world frame
  Vec3 inner_max_m = Vec3::Zero();
  double wall_thickness_m = 2.0e-3;
};

/// The static colliders of the ground and the box's five walls (either may be disabled).
std::vector<Collider> build_static_colliders(const GroundConfig& ground, const OpenBoxConfig& box);

/// An open box's five walls as static box colliders around the inner cavity [inner_min_m,
/// inner_max_m], each `wall_thickness_m` thick: the floor (under the cavity and the side walls),
/// then the sides at -x and +x (spanning y), then at -y and +y (between them); open at +z.
std::vector<Collider> open_box_walls(const Vec3& inner_min_m, const Vec3& inner_max_m,
                                     double wall_thickness_m);

}  // namespace acdr
