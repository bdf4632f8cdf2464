// Signed distance functions of the collider shapes (Quilez-style exact distances for box,
// capsule and spherical shell). Exact distances matter: the nucleus contact sphere-traces
// particle paths against them, which is only conservative when |sd| never overestimates.
#include "engine/geometry/collider.hpp"

#include <algorithm>
#include <cmath>

#include "engine/geometry/signed_distance_grid.hpp"

namespace acdr {
namespace {

/// Exact signed distance to an axis-aligned box of half extents `b` centred at the origin.
double box_distance(const Vec3& p, const Vec3& b, Vec3* normal) {
  // Scalar form (the nucleus calls this for every lattice site near a box).
  const double qx = std::abs(p.x()) - b.x(), qy = std::abs(p.y()) - b.y(),
               qz = std::abs(p.z()) - b.z();
  if (qx > 0.0 || qy > 0.0 || qz > 0.0) {
    // Outside: distance to the nearest point of the box.
    const double ox = std::max(qx, 0.0), oy = std::max(qy, 0.0), oz = std::max(qz, 0.0);
    const double d = std::sqrt(ox * ox + oy * oy + oz * oz);
    if (normal) {
      *normal = Vec3(std::copysign(ox, p.x()) / d, std::copysign(oy, p.y()) / d,
                     std::copysign(oz, p.z()) / d);
    }
    return d;
  }
  // Inside: the nearest face is the one with the largest (least negative) q.
  int axis = 0;
  double q = qx;
  if (qy > q) {
    axis = 1;
    q = qy;
  }
  if (qz > q) {
    axis = 2;
    q = qz;
  }
  if (normal) {
    *normal = Vec3::Zero();
    (*normal)[axis] = p[axis] >= 0.0 ? 1.0 : -1.0;
  }
  return q;
}

/// Capsule around the local z segment [-half_length, half_length].
double capsule_distance(const Vec3& p, double half_length, double radius, Vec3* normal) {
  const Vec3 c(0.0, 0.0, std::clamp(p.z(), -half_length, half_length));
  Vec3 r = p - c;
  double len = r.norm();
  if (normal) {
    if (len > 1e-15) {
      *normal = r / len;
    } else {
      *normal = Vec3::UnitX();  // on the axis: any radial direction
    }
  }
  return len - radius;
}

/// Lower hemispherical shell, centre at the origin, outer radius R, wall t, open toward +z.
/// Below the rim plane the distance is to the spherical shell; above it, to the rim annulus.
double cup_distance(const Vec3& p, double R, double t, Vec3* normal) {
  const double mid = R - 0.5 * t;
  if (p.z() <= 0.0) {
    const double len = p.norm();
    const Vec3 radial = len > 1e-15 ? Vec3(p / len) : Vec3(-Vec3::UnitZ());
    const double d = std::abs(len - mid) - 0.5 * t;
    // Inside the wall near the rim, the rim face (z = 0) may be the nearest surface.
    if (d < 0.0 && p.z() > d) {
      if (normal) *normal = Vec3::UnitZ();
      return p.z();
    }
    if (normal) *normal = len >= mid ? radial : Vec3(-radial);
    return d;
  }
  // Above the rim plane: distance to the annulus {z = 0, R - t <= rho <= R}.
  const double rho = std::hypot(p.x(), p.y());
  const double rho_c = std::clamp(rho, R - t, R);
  const Vec3 dir = rho > 1e-15 ? Vec3(p.x() / rho, p.y() / rho, 0.0) : Vec3(Vec3::UnitX());
  const Vec3 closest = rho_c * dir;
  const Vec3 r = p - closest;
  const double d = r.norm();
  if (normal) *normal = d > 1e-15 ? Vec3(r / d) : Vec3(Vec3::UnitZ());
  return d;
}

}  // namespace

double signed_distance_local(const Collider& c, const Vec3& local, Vec3* normal) {
  Vec3 n_local = Vec3::UnitZ();
  double d = 0.0;
  switch (c.kind) {
    case ColliderKind::kHalfSpace:
      d = local.z();
      n_local = Vec3::UnitZ();
      break;
    case ColliderKind::kBox:
      d = box_distance(local, c.half_extents_m, normal ? &n_local : nullptr);
      break;
    case ColliderKind::kCapsule:
      d = capsule_distance(local, c.half_length_m, c.radius_m, normal ? &n_local : nullptr);
      break;
    case ColliderKind::kCupShell:
      d = cup_distance(local, c.radius_m, c.thickness_m, normal ? &n_local : nullptr);
      break;
    case ColliderKind::kSdfGrid:  // anatomy: bone as a sampled distance field
      d = c.sdf ? c.sdf->distance(local, normal ? &n_local : nullptr) : 1.0;
      break;
  }
  if (normal) *normal = n_local;
  return d;
}

double signed_distance(const Collider& c, const Vec3& p, Vec3* normal) {
  const double d = signed_distance_local(c, c.pose.inverse_apply(p), normal);
  if (normal) *normal = c.pose.orientation * *normal;
  return d;
}

}  // namespace acdr
