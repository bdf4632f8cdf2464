// The engine's description of a scene: plain data, SI units, built once by the scenario loader
// (or by a test or benchmark) and never changed while a World runs. Each optional part is
// built only when present (`enabled`), so a scene pays only for what it declares.
#pragma once

#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include "engine/danger_zone.hpp"
#include "engine/signed_distance_grid.hpp"
#include "engine/types.hpp"
#include "engine/vertebra_generator.hpp"

namespace acdr {

/// One particle material (nucleus pulposus, annulus). Defaults: the seed's shortening-like
/// nucleus (seed Sec. IV.A: viscosity >= 250 Pa·s) at water-like density (REFERENCES.md).
struct MaterialConfig {
  std::string name = "nucleus";
  double density_kg_m3 = 1050.0;    ///< gel density, 1000-1100 usual (REFERENCES.md)
  double viscosity_Pa_s = 250.0;    ///< Newtonian shear viscosity mu (seed Eq. 2-3)
  double bond_stiffness_N_m = 5.0;  ///< spring stiffness k between bonded particles (Eq. 9)
  double bond_break_m = 0.3e-3;     ///< break stretch delta_max; a bond breaks at k*delta_max (Eq. 10)
  bool counts_as_target = true;     ///< removing it is the goal (nucleus) or a penalty (annulus)
  /// Bulk modulus of the particle pressure (density constraint), Pa: a penalty that keeps the
  /// water-rich gel nearly incompressible (hydrostatic compression of a 1 cm layer ~0.2 %).
  /// Not published for NP; 50 kPa is of the order of its measured moduli (5-60 kPa,
  /// REFERENCES.md) and keeps the buoyancy case within a few percent (docs/verification.md).
  double bulk_modulus_Pa = 5.0e4;
};

// --- anatomy (issue 4): particle regions of other shapes than a box, for the disc space ---
enum class BlockShape : std::uint8_t {
  kBox,               ///< the whole box [min, max]
  kEllipticCylinder,  ///< points of the box inside an elliptic cylinder along `axis`, less an
                      ///< optional elliptic hole: a nucleus (no hole) or an annulus ring
};
// --- end anatomy ---

/// A region filled with particles on a cubic lattice anchored at `min_m`: the box [min, max],
/// or (anatomy) the part of it inside an elliptic cylinder or ring. Blocks whose `min_m` differ
/// by whole multiples of the spacing share their lattice, so a nucleus, the annulus ring around
/// it and the cartilage endplate layers above and below it meet without a seam.
struct ParticleBlockConfig {
  Vec3 min_m = Vec3::Zero();
  Vec3 max_m = Vec3::Zero();
  int material = 0;  ///< index into NucleusConfig::materials
  // --- anatomy (issue 4) ---
  BlockShape shape = BlockShape::kBox;
  int axis = 1;                          ///< kEllipticCylinder: 0 x, 1 y, 2 z (the spine: y)
  Vec3 center_m = Vec3::Zero();          ///< ellipse centre (its `axis` coordinate is ignored)
  /// Outer semi-axes along the two other axes, in increasing axis order (for axis y: x then z).
  double semi_a_m = 0.0, semi_b_m = 0.0;
  /// Hole semi-axes (0: none). A ring: the annulus around a nucleus of these semi-axes.
  double hole_a_m = 0.0, hole_b_m = 0.0;
  /// Optional box left empty, e.g. the anterior window cut into the annulus for the approach.
  bool has_cutout = false;
  Vec3 cutout_min_m = Vec3::Zero(), cutout_max_m = Vec3::Zero();

  /// Whether point p belongs to the region (inside the box, the shape, not the hole or cutout).
  bool contains(const Vec3& p) const;
  // --- end anatomy ---
};

struct NucleusConfig {
  bool enabled = false;
  double spacing_m = 1.0e-3;            ///< lattice spacing h of the particles
  double bond_radius_factor = 1.5;      ///< particles closer than factor*h at start are bonded
  std::vector<MaterialConfig> materials;
  std::vector<ParticleBlockConfig> blocks;
};

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

enum class InstrumentShape { kPrism, kCupCurette };

/// The hand instrument. Its body frame has its origin at the grip point G (where the device
/// holds it); the shaft runs from G along local -z to the working tip T = (0, 0, -shaft_length).
struct InstrumentConfig {
  bool enabled = false;
  InstrumentShape shape = InstrumentShape::kPrism;
  double mass_kg = 0.03;
  double shaft_length_m = 0.08;     ///< grip to working tip
  double shaft_diameter_m = 2.0e-3; ///< round shaft; sets the yield moment
  double yield_stress_Pa = 500e6;   ///< surgical stainless steel, scenario-editable
  double warning_fraction = 0.5;    ///< moment above this fraction of yield is an overload warning
  /// Prism blade (seed Fig. 4-6): length along local x, width along y, height along z; its
  /// lower face is at the tip.
  Vec3 blade_size_m = Vec3(8.0e-3, 4.0e-3, 10.0e-3);
  double cup_diameter_m = 4.0e-3;   ///< cup curette: inner diameter of the cup
  double cup_depth_m = 2.0e-3;      ///< cup curette: depth of the cup
  double cup_wall_m = 0.4e-3;       ///< cup curette: wall thickness
  /// Cup curette: angle between the shaft's direction toward the tip and the cup's opening,
  /// rad. pi/2 opens sideways (a straight curette); larger angles turn the opening back toward
  /// the handle, as on an angled (reverse) curette, so a pull stroke loads the cup's floor.
  double cup_opening_angle_rad = 0.5 * std::numbers::pi;

  /// Bending moment at which the shaft yields: M_yield = sigma_y * pi * d^3 / 32.
  double yield_moment_Nm() const;
};

/// Virtual coupling between the device pose and the instrument (Colgate 1995; Adams &
/// Hannaford 1999). Critical damping is kd = 2*sqrt(m*ks).
struct CouplingConfig {
  double stiffness_N_m = 500.0;       ///< below the Phantom Omni's 700 N/m (REFERENCES.md)
  double damping_Ns_m = -1.0;         ///< < 0: critically damped from mass and stiffness
  double rot_stiffness_Nm_rad = 0.5;
  double rot_damping_Nms_rad = -1.0;  ///< < 0: critically damped from inertia
};

/// The haptic device the force is sent to (REFERENCES.md, Haptics).
struct DeviceConfig {
  std::string name = "Touch";
  double max_force_N = 3.3;
  double max_force_rate_N_s = 300.0;  ///< slew limit of the rendered force
  double ramp_in_s = 0.5;             ///< force ramps from zero at start (no start-up kick)
  double max_jump_m = 0.01;           ///< a pose jump larger than this in one packet is rejected
};

struct SolverConfig {
  double dt_s = 1.0e-3;          ///< fixed step (1 kHz haptic rate)
  int max_iterations = 60;       ///< linear solver iterations per substep
  double tolerance = 1.0e-4;     ///< relative residual of the linear solve
  bool sleep_enabled = true;     ///< particles at rest far from the instrument are not integrated
  double sleep_speed_m_s = 1.0e-4;
  double sleep_distance_m = 6.0e-3;
  /// Particle-collider contacts are looked for only where the collider's bounding box comes
  /// within reach of the particle (exact: a box farther away cannot hold a surface nearer).
  /// Off only to measure what the skip saves (acdr bench).
  bool contact_culling = true;
  /// The wall sums a particle gets from a collider's lattice sites (density, second moment,
  /// no-slip tensor; dozens of distance queries) are kept while the particle's place relative
  /// to the collider stays within `wall_sum_cache_tolerance` x spacing (and the collider
  /// turns less than that over the interaction radius): resting material by the box walls or
  /// bone, and material carried on the instrument, skip the queries for a sub-percent lag in
  /// those sums. Off to measure the skip (acdr bench).
  bool wall_sum_cache = true;
  double wall_sum_cache_tolerance = 0.005;
};

/// Region whose particles count as still in place; a particle that leaves it is removed.
struct RemovalRegionConfig {
  Vec3 min_m = Vec3::Zero();
  Vec3 max_m = Vec3::Zero();
};

// --- anatomy (issue 4) ---
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
  bool generate_zones = true;  ///< arteries, roots, cord/PLL, endplates (danger_zone.hpp)
  C4C5ZoneParams zone_params;
  /// More zones from the scenario. A kSdfBand zone names its bone in `bone` (0 C4, 1 C5).
  std::vector<DangerZone> extra_zones;
  /// Where meshes and grids are cached: "" the user's cache (XDG), "none" no caching.
  std::string cache_dir;
};

/// At most this many danger zones per scene (a Frame holds one sample per zone).
inline constexpr int kMaxZones = 16;
// --- end anatomy ---

struct WorldConfig {
  Vec3 gravity_m_s2 = Vec3(0.0, 0.0, -kStandardGravity);
  GroundConfig ground;
  OpenBoxConfig box;
  NucleusConfig nucleus;
  InstrumentConfig instrument;
  CouplingConfig coupling;
  DeviceConfig device;
  SolverConfig solver;
  RemovalRegionConfig removal;
  Pose instrument_start;  ///< grip pose at t = 0 (also the device pose until input arrives)
  AnatomyConfig anatomy;  ///< anatomy (issue 4)
};

}  // namespace acdr
