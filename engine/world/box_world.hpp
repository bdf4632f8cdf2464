// The seed's proof-of-concept scene as a WorldConfig (ground, open box, a block of nucleus, the
// prism instrument above it), at any size: shared by tests, stress cases and benchmarks.
#pragma once

#include "engine/world/world_config.hpp"

namespace acdr {

struct BoxWorldOptions {
  Vec3 cavity_m = Vec3(10e-3, 10e-3, 8e-3);  ///< inner size, centred on x = y = 0, floor z = 0
  double fill_height_m = 4e-3;               ///< nucleus fills the cavity up to here
  double spacing_m = 1e-3;
  MaterialConfig material;                   ///< defaults: the seed's 250 Pa·s nucleus
  bool nucleus = true;
  Vec3 blade_m = Vec3(4e-3, 4e-3, 1e-3);
  double shaft_length_m = 0.05;
  double grip_height_m = 0.07;               ///< start grip z (blade well above the nucleus)
};

/// Removal region = the cavity (with 1 mm below the floor).
WorldConfig make_box_world(const BoxWorldOptions& options = {});

}  // namespace acdr
