// Danger zones: structures the instrument must stay clear of (vertebral arteries, nerve
// roots, spinal cord and posterior longitudinal ligament, endplates). Each zone is a solid
// shape with a warning distance, a force limit and whether entering it is a never-event; each
// step the engine measures the closest distance between the instrument and every zone.
//
// Distances are between solids (m): positive apart, negative when the instrument overlaps
// the zone. The instrument side is exact for its shaft against capsule and sphere zones and
// found by a bounded search elsewhere (the cup by its sphere and rim, the shaft by a
// Lipschitz march, blade faces by a lattice and pattern search), within ~0.01 mm for convex
// zones; beyond `kZoneFarDistance` only a lower bound is computed. No allocation.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "engine/geometry/collider.hpp"
#include "engine/geometry/signed_distance_grid.hpp"
#include "engine/anatomy/vertebra_generator.hpp"

namespace acdr {

/// Beyond this (m) a zone's distance is reported as a lower bound, not refined.
inline constexpr double kZoneFarDistance = 0.02;

enum class ZoneShape : std::uint8_t {
  kSphere,   ///< centre `a_m`, `radius_m`
  kCapsule,  ///< segment `a_m`-`b_m`, `radius_m`; with `bent`, the path `a_m`-`b_m`-`c_m`
  kBox,      ///< centre `a_m`, `half_extents_m`, `orientation`; edges rounded by `radius_m`
  kSdfBand,  ///< points within `band_m` of the surface of `sdf` (inside counts) and inside
             ///< the axis-aligned `region` box: e.g. an endplate of a vertebra
};

const char* zone_shape_name(ZoneShape shape);

struct DangerZone {
  std::string name;                    ///< e.g. "vertebral_artery_left"
  ZoneShape shape = ZoneShape::kSphere;
  Vec3 a_m = Vec3::Zero();
  Vec3 b_m = Vec3::Zero();
  Vec3 c_m = Vec3::Zero();  ///< kCapsule with `bent`: the path goes on from `b_m` to here
  bool bent = false;
  double radius_m = 0.0;    ///< sphere and capsule radius; a box's edge rounding (0: sharp)
  Vec3 half_extents_m = Vec3::Zero();
  Quat orientation = Quat::Identity();
  const SignedDistanceGrid* sdf = nullptr;  ///< kSdfBand; not owned (the World owns grids)
  double band_m = 0.0;
  Vec3 region_min_m = Vec3::Zero();
  Vec3 region_max_m = Vec3::Zero();

  int bone = -1;  ///< kSdfBand declared in a scenario: 0 C4, 1 C5 (the World then sets `sdf`)

  double warning_distance_m = 2.0e-3;  ///< closer than this: a warning
  double force_limit_N = 1.0;          ///< instrument force allowed near the zone
  bool never_event = false;            ///< entering fails the attempt (artery, root, cord)

  /// Signed distance from a point to the zone's solid (m), negative inside.
  double signed_distance(const Vec3& p) const;
};

/// One zone's state in one step.
struct ZoneSample {
  double distance_m = 0.0;  ///< closest instrument-zone distance, negative when overlapping
  bool inside = false;      ///< distance < 0
  bool warning = false;     ///< distance < warning distance
  double force_N = 0.0;     ///< instrument force magnitude while within the warning distance
};

/// Closest distance between one instrument collider and a zone (m, negative overlapping).
double zone_collider_distance(const DangerZone& zone, const Collider& collider);

/// Fills `out[i]` for `zones[i]` (out.size() >= zones.size()). `instrument_force_N` is the
/// force the instrument exerts on the tissue (rigid contact plus nucleus reaction); it counts
/// against a zone while the instrument is within the zone's warning distance.
void evaluate_zones(std::span<const DangerZone> zones, std::span<const Collider> instrument,
                    const Vec3& instrument_force_N, std::span<ZoneSample> out);

/// Clinical defaults of the generated zones (scenario-editable). No published force limits
/// were found (docs/references.md): these are documented defaults.
struct C4C5ZoneParams {
  /// Vertebral artery radius: it fills most of its ~5.5 mm foramen. Default 1.9 mm.
  double artery_radius_m = 1.9e-3;
  /// The lateral limit of a discectomy lies 3-5 mm short of the artery (AO Surgery Reference).
  double artery_warning_m = 3.0e-3;
  double artery_force_limit_N = 0.5;
  /// Exiting root radius. Default 1.5 mm.
  double root_radius_m = 1.5e-3;
  /// 2 mm warning band, as around the vertebral foramen in volumetric drilling trainers
  /// (kvenkatesh5/volumetric_drilling_laminectomy: 2 and 4 mm bands).
  double root_warning_m = 2.0e-3;
  double root_force_limit_N = 0.3;
  double cord_warning_m = 1.5e-3;
  double cord_force_limit_N = 0.5;
  /// Endplates: the curette works against them; a warning only very close, force limited.
  double endplate_warning_m = 0.3e-3;
  double endplate_force_limit_N = 3.0;
  /// How far the endplate band reaches into the bone (m).
  double endplate_depth_m = 3.0e-3;
};

/// The zones generated with the anatomy, in this order: vertebral_artery_left/right,
/// nerve_root_left/right, spinal_cord_pll, then endplate_c4_lower and endplate_c5_upper when
/// the vertebra's own signed distance grid is given (a band on it, clipped to the endplate;
/// one grid per vertebra, so the neighbour's bone never stands in for the zone's).
std::vector<DangerZone> make_c4c5_zones(const SegmentParams& params, const SegmentLandmarks& l,
                                        const SignedDistanceGrid* c4_bone,
                                        const SignedDistanceGrid* c5_bone,
                                        const C4C5ZoneParams& zone_params = {});

/// Closest distance between segments p1-q1 and p2-q2 (Ericson, Real-Time Collision
/// Detection, 5.1.9).
double segment_segment_distance(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2);

}  // namespace acdr
