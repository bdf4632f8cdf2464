// What a scene says about its anatomy: the C4-C5 segment's morphometry or mesh files, the
// bone distance grid for the particles, and the danger zones (plain data, SI units).
#pragma once

#include <string>
#include <vector>

#include "engine/anatomy/danger_zone.hpp"
#include "engine/anatomy/vertebra_generator.hpp"
#include "engine/geometry/signed_distance_grid.hpp"

namespace acdr {

/// The C4-C5 scene: two vertebrae (generated from morphometry, or loaded from OBJ/STL files in
/// the segment frame, docs/anatomy.md), a signed distance grid of the bone for particle
/// contact, and the danger zones. Bone is static: Bullet triangle meshes for the instrument,
/// the grid (collider kSdfGrid) for the particles.
struct AnatomyConfig {
  bool enabled = false;
  /// Morphometry: shapes the procedural vertebrae, places the disc space, the generated zones
  /// and the default particle-contact grid region (also with loaded meshes).
  SegmentParams segment;
  /// Both set: load these meshes (closed surfaces, segment frame) instead of generating.
  std::string c4_mesh_path;
  std::string c5_mesh_path;
  double mesh_unit_m = 1e-3;  ///< metres per mesh file unit (files carry none)
  /// Particle-contact grid. Without `clip` it covers the disc space and 3-4 mm around it.
  SdfGridParams sdf;
  /// Spacing of each vertebra's own grid, used by the endplate zones (m).
  double zone_sdf_spacing_m = 0.5e-3;
  /// The posterior longitudinal ligament as a wall for the particles (not for the instrument)
  /// across the back of the disc space: disc material pushed backward stops at it instead of
  /// entering the spinal canal (Anatomy::posterior_ligament_collider).
  bool posterior_ligament = false;
  bool generate_zones = true;  ///< arteries, roots, cord/PLL, endplates (danger_zone.hpp)
  C4C5ZoneParams zone_params;
  /// More zones from the scenario. A kSdfBand zone names its bone in `bone` (0 C4, 1 C5).
  std::vector<DangerZone> extra_zones;
  /// Where meshes and grids are cached: "" the user's cache (XDG), "none" no caching.
  std::string cache_dir;
  /// Loads on the bone for its finite-element model (engine/core/bone_load.hpp): sampled every
  /// this much simulated time (s); 0: not sampled.
  double bone_load_period_s = 0.0;
  /// The nucleus's reaction on the bone is gathered over cubic cells this wide (m); each cell
  /// becomes one load spread over half its width.
  double bone_load_cell_m = 2.0e-3;
};

/// At most this many danger zones per scene (a Frame holds one sample per zone).
inline constexpr int kMaxZones = 16;

}  // namespace acdr
