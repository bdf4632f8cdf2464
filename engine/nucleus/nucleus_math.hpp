// Small functions the nucleus's stages share: the density and viscous kernels, the occupancy
// of lattice sites by a solid, poses and frames, collider bounds, and symmetric 3x3 blocks.
// Internal to engine/nucleus.
#pragma once

#include <algorithm>
#include <cmath>

#include "engine/core/types.hpp"
#include "engine/geometry/collider.hpp"
#include "engine/geometry/signed_distance_grid.hpp"
#include "engine/nucleus/nucleus_workspace.hpp"

namespace acdr::nucleus {

/// Density kernel w(r) = (1 - r/R)^3 (the "spiky" shape of Desbrun & Gascuel 1996, used for
/// pressure by Mueller et al., SCA 2003), w(0) = 1. Its slope is steepest at r = 0, so two
/// particles pushed together are pushed apart harder the closer they are; the poly6 shape's
/// slope vanishes at r = 0 and let clumps of overlapped particles jitter at high pressure.
/// In terms of q = max(0, 1 - r/R): w = q^3, dw/dr = -3 q^2 / R.
inline double kernel_of(double q) { return q * q * q; }
inline double kernel(double r, double R) { return r >= R ? 0.0 : kernel_of(1.0 - r / R); }

/// Weight of a pair in the viscous operator: (1 - r/R)^1.25 on R = 1.98 h. Chosen by lattice
/// sums (the viscosity of the pair operator under simple shear, T / S relative to rest) so
/// that the effective viscosity hardly depends on how the lattice is sheared: layers sliding
/// past each other along an axis by any fraction of h change it by -3.6..0 %, along a face
/// diagonal by -1.6..+0.4 % (the sharp 18-neighbour stencil, exact at rest, loses up to 45 %
/// when a neighbour shell leaves the cut-off), and shear along a face diagonal is within
/// 1.2 % of shear along an axis. The earlier (1 - r/R)^1.5 on R = 2.1 h (32 neighbours; by the
/// same sums 0..+1.8 %, 6.8 %) costs a fifth more pairs; cutting that radius without a
/// flatter weight makes the operator anisotropic (R = 1.75 h: +51 % along a diagonal).
/// In terms of q = max(0, 1 - r/R): q^1.25.
inline double viscous_weight_of(double q) { return q * std::sqrt(std::sqrt(q)); }
inline double viscous_weight(double r, double R) {
  return r >= R ? 0.0 : viscous_weight_of(1.0 - r / R);
}

/// Smooth occupancy of a lattice site by a solid from its signed distance: 1 a half spacing
/// inside, 0 a half spacing outside, smoothstep between (zero slope at both ends, so a
/// particle resting at the contact distance feels no jump in stiffness).
inline double occupancy(double sd, double h, double* slope) {
  const double t = std::clamp(0.5 - sd / h, 0.0, 1.0);
  if (slope) *slope = (t <= 0.0 || t >= 1.0) ? 0.0 : 6.0 * t * (1.0 - t) * (-1.0 / h);
  return t * t * (3.0 - 2.0 * t);
}

/// Pose advanced by a constant velocity over dt.
inline Pose advance(const Pose& p, const Vec3& v, const Vec3& w, double dt) {
  Pose out = p;
  out.position = p.position + v * dt;
  const double angle = w.norm() * dt;
  if (angle > 0.0) {
    out.orientation = Quat(Eigen::AngleAxisd(angle, w.normalized())) * p.orientation;
    out.orientation.normalize();
  }
  return out;
}

/// World point x in a pose's frame; `identity`: the pose is unrotated, and the rotation (exact
/// for the identity quaternion) is skipped.
inline Vec3 to_local(const Pose& pose, bool identity, const Vec3& x) {
  return identity ? Vec3(x - pose.position) : pose.inverse_apply(x);
}

inline bool finite(const Vec3& v) {
  return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}

/// World-space bounding box of a collider; false when it has none (a half-space).
inline bool collider_bounds(const Collider& c, Vec3* lo, Vec3* hi) {
  Vec3 e = Vec3::Zero();
  switch (c.kind) {
    case ColliderKind::kHalfSpace: return false;
    // Bone: the sampled field may be clipped to the disc space while the bone goes on beyond
    // it, so no box bounds the solid; it is tested for every particle (one trilinear lookup).
    case ColliderKind::kSdfGrid: return false;
    case ColliderKind::kBox:
      e = c.pose.orientation.toRotationMatrix().cwiseAbs() * c.half_extents_m;
      break;
    case ColliderKind::kCapsule:
      e = c.pose.orientation.toRotationMatrix().cwiseAbs() * Vec3(0, 0, c.half_length_m) +
          Vec3::Constant(c.radius_m);
      break;
    case ColliderKind::kCupShell: e = Vec3::Constant(c.radius_m); break;
  }
  *lo = c.pose.position - e;
  *hi = c.pose.position + e;
  return true;
}

/// How fast a collider's signed distance can change per metre moved (in its own frame): 1 for
/// the exact shapes, the sampled bone's gradient bound plus 1 (its distance beyond the grid's
/// box is added to the clamped lookup). |sd(p) - sd(q)| <= slope |p - q| for any p, q.
inline double distance_slope_bound(const Collider& c) {
  if (c.kind == ColliderKind::kSdfGrid && c.sdf != nullptr) return c.sdf->gradient_bound() + 1.0;
  return 1.0;
}

/// Distance from p to the box [lo, hi] (0 inside): a lower bound of the distance to any solid
/// inside the box.
inline double box_gap2(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  return (lo - p).cwiseMax(p - hi).cwiseMax(0.0).squaredNorm();
}
inline double box_gap(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  return std::sqrt(box_gap2(p, lo, hi));
}

/// Symmetric 3x3 blocks (Sym3: xx, yy, zz, xy, xz, yz): m += a n n^T, the inverse, m v.
inline void add_outer(Sym3& m, double a, const Vec3& n) {
  m[0] += a * n.x() * n.x();
  m[1] += a * n.y() * n.y();
  m[2] += a * n.z() * n.z();
  m[3] += a * n.x() * n.y();
  m[4] += a * n.x() * n.z();
  m[5] += a * n.y() * n.z();
}

/// Inverse of a symmetric positive definite 3x3 block (adjugate over determinant).
inline Sym3 inverse(const Sym3& m) {
  const double xx = m[0], yy = m[1], zz = m[2], xy = m[3], xz = m[4], yz = m[5];
  const double c00 = yy * zz - yz * yz;
  const double c01 = xz * yz - xy * zz;
  const double c02 = xy * yz - xz * yy;
  const double det = xx * c00 + xy * c01 + xz * c02;
  const double inv = 1.0 / det;
  return {c00 * inv,
          (xx * zz - xz * xz) * inv,
          (xx * yy - xy * xy) * inv,
          c01 * inv,
          c02 * inv,
          (xy * xz - xx * yz) * inv};
}

inline Vec3 mul(const Sym3& m, const Vec3& v) {
  return Vec3(m[0] * v.x() + m[3] * v.y() + m[4] * v.z(),
              m[3] * v.x() + m[1] * v.y() + m[5] * v.z(),
              m[4] * v.x() + m[5] * v.y() + m[2] * v.z());
}

}  // namespace acdr::nucleus
