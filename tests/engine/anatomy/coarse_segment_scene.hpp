// A coarse C4-C5 scene that builds in about a second (coarse surfaces and grids, a 1 mm
// nucleus, the cup curette 1 mm in front of the disc space), and the push that brings the cup
// down onto C5's endplate. Shared by the anatomy, world and bone tests.
#pragma once

#include <string>

#include "engine/world/world_config.hpp"

namespace acdr::test {

/// The coarse anatomy, cached in `cache_dir` ("none": no caching).
inline AnatomyConfig coarse_anatomy(const std::string& cache_dir) {
  AnatomyConfig a;
  a.enabled = true;
  a.segment.mesh_spacing_m = 0.9e-3;
  a.sdf.spacing_m = 0.5e-3;
  a.zone_sdf_spacing_m = 0.8e-3;
  a.cache_dir = cache_dir;
  return a;
}

/// The coarse anatomy with a nucleus between the endplates and the cup curette in front.
inline WorldConfig coarse_segment_world(const std::string& cache_dir) {
  constexpr double kMm = 1e-3;
  WorldConfig w;
  w.anatomy = coarse_anatomy(cache_dir);
  w.gravity_m_s2 = Vec3(0, 0, -kStandardGravity);
  w.nucleus.enabled = true;
  w.nucleus.spacing_m = 1.0e-3;
  w.nucleus.materials.emplace_back();
  ParticleBlockConfig nucleus;
  nucleus.min_m = Vec3(-4, -2.95, -4) * kMm;
  nucleus.max_m = Vec3(4, 2.95, 3) * kMm;
  nucleus.shape = BlockShape::kEllipticCylinder;
  nucleus.center_m = Vec3(0, 0, -0.5) * kMm;
  nucleus.semi_a_m = 4 * kMm;
  nucleus.semi_b_m = 3.5 * kMm;
  w.nucleus.blocks.push_back(nucleus);
  w.removal.min_m = Vec3(-10, -3.5, -8.5) * kMm;
  w.removal.max_m = Vec3(10, 3.5, 9) * kMm;
  w.instrument.enabled = true;
  w.instrument.shape = InstrumentShape::kCupCurette;
  w.instrument.cup_diameter_m = 3 * kMm;
  // The cup 1 mm in front of the disc space, shaft along -z (the approach from anterior).
  w.instrument_start.position = Vec3(0, 0, (9.05 + 1.9 + 80) * kMm);
  return w;
}

/// Where the device holds the grip to push the cup down onto C5's endplate's front edge.
inline Pose coarse_segment_push(const WorldConfig& w) {
  Pose p = w.instrument_start;
  p.position += Vec3(0, -3e-3, -6e-3);
  return p;
}

}  // namespace acdr::test
