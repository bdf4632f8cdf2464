// The box module's nucleus scene, shared by tests, stress cases and benchmarks (never copied):
// the seed's open box (30 x 20 x 12 mm cavity, 2 mm walls, floor at z = 0) holding a
// 30 x 20 x 8 mm block of the default material at 1 mm spacing, and a prism blade.
#pragma once

#include <vector>

#include "engine/geometry/collider.hpp"
#include "engine/world/world_config.hpp"

namespace acdr {

struct BoxBlockScene {
  NucleusConfig nucleus;
  SolverConfig solver;
  Vec3 gravity = Vec3(0.0, 0.0, -kStandardGravity);
  std::vector<Collider> statics;  ///< floor and four walls
  Collider blade;                 ///< 8 x 4 x 10 mm prism blade (body 0), above the block
};

/// The scene with the given spacing and material (defaults: the box module's).
BoxBlockScene make_box_block_scene(double spacing_m = 1.0e-3,
                                   const MaterialConfig& material = MaterialConfig{});

}  // namespace acdr
