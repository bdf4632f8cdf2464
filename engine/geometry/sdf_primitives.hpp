// Signed distance functions of simple solids (negative inside, metres) and the smooth
// blending used to build bone shapes from them (Quilez, "distance functions" and "smooth
// minimum", iquilezles.org; Hart 1996 for sphere tracing bounds). Exact for the primitives;
// blends and cuts give a bound, enough to place a surface.
#pragma once

#include <algorithm>
#include <cmath>

#include "engine/core/types.hpp"

namespace acdr::sdf {

inline double sphere(const Vec3& p, const Vec3& c, double r) { return (p - c).norm() - r; }

/// Distance from p to the segment a-b.
inline double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

/// Capsule: all points within r of the segment a-b.
inline double capsule(const Vec3& p, const Vec3& a, const Vec3& b, double r) {
  return segment_distance(p, a, b) - r;
}

/// Axis-aligned box centred at c with half extents e, edges rounded by `round` (<= min e).
inline double box(const Vec3& p, const Vec3& c, const Vec3& e, double round = 0.0) {
  const Vec3 q = (p - c).cwiseAbs() - (e - Vec3::Constant(round));
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0) - round;
}

/// Box in a rotated frame: `to_local` maps world offsets (p - c) to box axes.
inline double oriented_box(const Vec3& p, const Vec3& c, const Eigen::Matrix3d& to_local,
                           const Vec3& e, double round = 0.0) {
  return box(to_local * (p - c), Vec3::Zero(), e, round);
}

/// Rectangle with rounded corners in 2-D (centre 0, half extents e, corner radius r).
inline double rounded_rect(double x, double y, double ex, double ey, double r) {
  const double qx = std::abs(x) - ex + r, qy = std::abs(y) - ey + r;
  return std::hypot(std::max(qx, 0.0), std::max(qy, 0.0)) + std::min(std::max(qx, qy), 0.0) - r;
}

/// Extrudes a 2-D distance d2 over |h| <= half_height with edges rounded by `round`.
inline double extrude(double d2, double h, double half_height, double round) {
  const double wx = d2 + round, wy = std::abs(h) - half_height + round;
  return std::min(std::max(wx, wy), 0.0) + std::hypot(std::max(wx, 0.0), std::max(wy, 0.0)) - round;
}

/// Infinite cylinder of radius r around the line through c along unit axis u.
inline double cylinder(const Vec3& p, const Vec3& c, const Vec3& u, double r) {
  const Vec3 d = p - c;
  return (d - d.dot(u) * u).norm() - r;
}

/// Half-space of points behind the plane through c with unit normal n (solid where n.(p-c) < 0).
inline double half_space(const Vec3& p, const Vec3& c, const Vec3& n) { return n.dot(p - c); }

/// Smooth union with blend radius k (polynomial smooth minimum; k = 0 is min).
inline double smooth_union(double a, double b, double k) {
  if (k <= 0.0) return std::min(a, b);
  const double h = std::clamp(0.5 + 0.5 * (b - a) / k, 0.0, 1.0);
  return b + (a - b) * h - k * h * (1.0 - h);
}

/// Smooth subtraction: a with b removed, fillet k.
inline double smooth_subtract(double a, double b, double k) { return -smooth_union(-a, b, k); }

inline double unite(double a, double b) { return std::min(a, b); }
inline double intersect(double a, double b) { return std::max(a, b); }
inline double subtract(double a, double b) { return std::max(a, -b); }

}  // namespace acdr::sdf
