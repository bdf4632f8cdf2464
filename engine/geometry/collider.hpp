// Solid shapes the particles touch: ground, box walls, bone, and the moving instrument.
// Each is a signed distance (negative inside) in the collider's pose, evaluated per particle,
// so a particle can be pushed out along the surface normal without tunnelling.
#pragma once

#include <cstdint>

#include "engine/core/types.hpp"

namespace acdr {

class SignedDistanceGrid;  // anatomy: engine/geometry/signed_distance_grid.hpp

enum class ColliderKind : std::uint8_t {
  kHalfSpace,  ///< solid below the local plane z = 0 (normal +z)
  kBox,        ///< solid box, half extents in the local frame
  kCapsule,    ///< segment from local (0,0,-half_length) to (0,0,+half_length), radius
  kCupShell,   ///< hemispherical cup: spherical shell of `radius` and `thickness`, open at local +z
  /// Bone: the sampled signed distance of a closed mesh, `sdf`, in the local
  /// frame. Trilinear: exact at grid points, within a few micrometres of the true distance
  /// near bone at 0.25 mm spacing (it may overestimate that little near convex edges).
  kSdfGrid,
};

/// A solid obstacle. `pose` places the local frame; velocities are those of that frame's origin.
struct Collider {
  ColliderKind kind = ColliderKind::kBox;
  Pose pose;
  Vec3 half_extents_m = Vec3::Zero();  ///< kBox
  double radius_m = 0.0;               ///< kCapsule, kCupShell (outer radius)
  double half_length_m = 0.0;          ///< kCapsule
  double thickness_m = 0.0;            ///< kCupShell wall
  const SignedDistanceGrid* sdf = nullptr;  ///< kSdfGrid; not owned (the World's anatomy owns it)
  Vec3 linear_velocity_m_s = Vec3::Zero();
  Vec3 angular_velocity_rad_s = Vec3::Zero();
  int body = -1;  ///< which moving body it belongs to (reactions are summed per body); -1 static
  /// The gel slides on this surface: the particles' no-slip (viscous) coupling to it is off and
  /// only its contact pushes them out (a rongeur's open jaws shaken over the tray).
  bool slip = false;
  /// Only the particles meet it; the instrument passes through (a ligament that holds the gel
  /// back but that a blade cuts). The rigid world leaves it out.
  bool particles_only = false;

  /// Velocity of the collider's material at world point p.
  Vec3 velocity_at(const Vec3& p) const {
    return linear_velocity_m_s + angular_velocity_rad_s.cross(p - pose.position);
  }
};

/// Signed distance from world point p to the collider's surface (m, negative inside) and the
/// outward unit normal at the closest surface point.
double signed_distance(const Collider& c, const Vec3& p, Vec3* normal);

/// The same in the collider's local frame: `local_p` and the returned normal are local.
/// Exact (never overestimates |distance|), so it can be sphere-traced.
double signed_distance_local(const Collider& c, const Vec3& local_p, Vec3* local_normal);

/// Force and torque the particles exert on one moving body in a step, and the linearised
/// drag d(force)/d(velocity) the body should treat implicitly for stability.
struct BodyReaction {
  Vec3 force_N = Vec3::Zero();
  Vec3 torque_Nm = Vec3::Zero();      ///< about `reference_point`
  Vec3 reference_point = Vec3::Zero();
  double drag_Ns_m = 0.0;             ///< >= 0, sum of viscous coupling coefficients
  double rot_drag_Nms = 0.0;          ///< >= 0, about the reference point
};

}  // namespace acdr
