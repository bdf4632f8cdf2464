// Danger zone distances: exact where closed forms exist, Lipschitz-bounded sampling elsewhere.
#include "engine/anatomy/danger_zone.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "engine/geometry/sdf_primitives.hpp"

namespace acdr {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kSurfaceStep = 1.0e-3;  // lattice on blade faces, refined by pattern search
constexpr double kSegmentStep = 0.5e-3;  // samples along the shaft, refined by golden section

/// Golden-section refinement of a 1-D minimum bracketed in [lo, hi] (12 steps: 0.3 % of it).
template <class F>
double refine_1d(F&& f, double lo, double hi, double best) {
  constexpr double kInvPhi = 0.6180339887498949;
  double x1 = hi - kInvPhi * (hi - lo), x2 = lo + kInvPhi * (hi - lo);
  double f1 = f(x1), f2 = f(x2);
  for (int i = 0; i < 12; ++i) {
    if (f1 < f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - kInvPhi * (hi - lo);
      f1 = f(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + kInvPhi * (hi - lo);
      f2 = f(x2);
    }
  }
  return std::min({best, f1, f2});
}

/// Minimum of the zone distance along segment a-b: samples kSegmentStep apart, skipping ahead
/// where the distance is far above the best so far (it is 1-Lipschitz along the segment, so
/// no skipped point can beat the best), then a golden-section refinement around the best.
double min_along_segment(const DangerZone& z, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len = ab.norm();
  if (len == 0.0) return z.signed_distance(a);
  const Vec3 u = ab / len;
  const auto g = [&](double t) { return z.signed_distance(a + t * u); };
  double best = kInf, t_best = 0.0, t = 0.0;
  for (;;) {
    const double v = g(t);
    if (v < best) {
      best = v;
      t_best = t;
    }
    if (t >= len) break;
    t = std::min(len, t + std::max(kSegmentStep, v - best));
  }
  return refine_1d(g, std::max(0.0, t_best - kSegmentStep), std::min(len, t_best + kSegmentStep), best);
}

/// Minimum of the zone distance over a parametrised surface patch: a lattice of samples about
/// kSurfaceStep apart, then a pattern search around the best sample with halving steps, which
/// converges for convex zones (distance restricted to a plane or sphere patch).
template <class Point>
double min_over_patch(const DangerZone& z, Point&& point, double u0, double u1, double v0, double v1,
                      int nu, int nv) {
  double best = kInf, bu = u0, bv = v0;
  for (int i = 0; i < nu; ++i) {
    const double u = nu > 1 ? u0 + (u1 - u0) * i / (nu - 1) : 0.5 * (u0 + u1);
    for (int j = 0; j < nv; ++j) {
      const double v = nv > 1 ? v0 + (v1 - v0) * j / (nv - 1) : 0.5 * (v0 + v1);
      const double d = z.signed_distance(point(u, v));
      if (d < best) {
        best = d;
        bu = u;
        bv = v;
      }
    }
  }
  double du = nu > 1 ? 0.5 * (u1 - u0) / (nu - 1) : 0.0, dv = nv > 1 ? 0.5 * (v1 - v0) / (nv - 1) : 0.0;
  for (int iter = 0; iter < 8; ++iter) {
    bool moved = false;
    for (const auto& [su, sv] : {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}}) {
      const double u = std::clamp(bu + su * du, u0, u1), v = std::clamp(bv + sv * dv, v0, v1);
      const double d = z.signed_distance(point(u, v));
      if (d < best) {
        best = d;
        bu = u;
        bv = v;
        moved = true;
      }
    }
    if (!moved) {
      du *= 0.5;
      dv *= 0.5;
    }
  }
  return best;
}

double box_collider_distance(const DangerZone& z, const Collider& c) {
  double best = kInf;
  const Eigen::Matrix3d R = c.pose.orientation.toRotationMatrix();
  const Vec3& e = c.half_extents_m;
  for (int axis = 0; axis < 3; ++axis) {
    for (double sign : {1.0, -1.0}) {
      const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
      const Vec3 centre = c.pose.position + sign * e[axis] * R.col(axis);
      // Skip a face that cannot hold a closer point.
      if (z.signed_distance(centre) - std::hypot(e[ua], e[va]) >= best) continue;
      const int nu = static_cast<int>(std::ceil(2.0 * e[ua] / kSurfaceStep)) + 1;
      const int nv = static_cast<int>(std::ceil(2.0 * e[va] / kSurfaceStep)) + 1;
      const Vec3 du = R.col(ua), dv = R.col(va);
      best = std::min(best, min_over_patch(z, [&](double u, double v) { return Vec3(centre + u * du + v * dv); },
                                           -e[ua], e[ua], -e[va], e[va], nu, nv));
    }
  }
  return best;
}

/// Cup: a hemispherical shell (outer radius R, open toward local +z). Seen from a zone, the
/// nearest point of the solid hemisphere lies on the outer sphere when the zone is on the
/// closed side (distance = d(centre) - R, exact for convex zones), else on the rim: then
/// both rim circles are searched. Typically 7 zone evaluations.
double cup_collider_distance(const DangerZone& z, const Collider& c) {
  const Vec3& o = c.pose.position;
  const double R = c.radius_m;
  const double dc = z.signed_distance(o);
  // Direction from the centre toward the zone: minus the gradient (central differences).
  constexpr double h = 0.05e-3;
  Vec3 grad;
  for (int k = 0; k < 3; ++k) {
    Vec3 e = Vec3::Zero();
    e[k] = h;
    grad[k] = (z.signed_distance(o + e) - z.signed_distance(o - e)) / (2.0 * h);
  }
  const Vec3 opening = c.pose.orientation * Vec3::UnitZ();
  if (-grad.dot(opening) <= 0.0 || grad.squaredNorm() == 0.0) return dc - R;
  // Zone on the open side: search the outer and inner rim circles.
  const Vec3 ex = c.pose.orientation * Vec3::UnitX(), ey = c.pose.orientation * Vec3::UnitY();
  double best = kInf;
  for (double r : {R, R - c.thickness_m}) {
    if (r <= 0.0) continue;
    const auto g = [&](double az) { return z.signed_distance(o + r * (std::cos(az) * ex + std::sin(az) * ey)); };
    constexpr int kAround = 16;
    double local = kInf, az_best = 0.0;
    for (int j = 0; j < kAround; ++j) {
      const double az = 2.0 * std::numbers::pi * j / kAround;
      const double v = g(az);
      if (v < local) {
        local = v;
        az_best = az;
      }
    }
    const double step = 2.0 * std::numbers::pi / kAround;
    best = std::min(best, refine_1d(g, az_best - step, az_best + step, local));
  }
  return best;
}

double bounding_radius(const Collider& c) {
  switch (c.kind) {
    case ColliderKind::kBox: return c.half_extents_m.norm();
    case ColliderKind::kCapsule: return c.half_length_m + c.radius_m;
    case ColliderKind::kCupShell: return c.radius_m;
    default: return kInf;
  }
}

}  // namespace

const char* zone_shape_name(ZoneShape shape) {
  switch (shape) {
    case ZoneShape::kSphere: return "sphere";
    case ZoneShape::kCapsule: return "capsule";
    case ZoneShape::kBox: return "box";
    case ZoneShape::kSdfBand: return "sdf_band";
  }
  return "?";
}

double segment_segment_distance(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2) {
  const Vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  constexpr double eps = 1e-30;
  double s = 0.0, t = 0.0;
  if (a <= eps && e <= eps) {
    // Both segments are points.
  } else if (a <= eps) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= eps) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 0.0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return ((p1 + s * d1) - (p2 + t * d2)).norm();
}

double DangerZone::signed_distance(const Vec3& p) const {
  switch (shape) {
    case ZoneShape::kSphere: return sdf::sphere(p, a_m, radius_m);
    case ZoneShape::kCapsule: {
      const double d = sdf::capsule(p, a_m, b_m, radius_m);
      return bent ? std::min(d, sdf::capsule(p, b_m, c_m, radius_m)) : d;
    }
    case ZoneShape::kBox:
      return sdf::box(orientation.conjugate() * (p - a_m), Vec3::Zero(), half_extents_m, radius_m);
    case ZoneShape::kSdfBand: {
      const Vec3 c = 0.5 * (region_min_m + region_max_m), e = 0.5 * (region_max_m - region_min_m);
      const double region = sdf::box(p, c, e);
      // Far outside the region the grid is not needed: the region bounds the distance.
      if (region > kZoneFarDistance || sdf == nullptr) return region;
      return std::max(sdf->distance(p) - band_m, region);
    }
  }
  return kInf;
}

double zone_collider_distance(const DangerZone& z, const Collider& c) {
  // Cheap lower bound first: far zones are not refined.
  const double bound = z.signed_distance(c.pose.position) - bounding_radius(c);
  if (bound > kZoneFarDistance) return bound;
  switch (c.kind) {
    case ColliderKind::kCapsule: {
      const Vec3 a = c.pose.apply(Vec3(0, 0, -c.half_length_m));
      const Vec3 b = c.pose.apply(Vec3(0, 0, c.half_length_m));
      if (z.shape == ZoneShape::kCapsule || z.shape == ZoneShape::kSphere) {
        const Vec3 zb = z.shape == ZoneShape::kCapsule ? z.b_m : z.a_m;
        double d = segment_segment_distance(a, b, z.a_m, zb);
        if (z.shape == ZoneShape::kCapsule && z.bent) d = std::min(d, segment_segment_distance(a, b, z.b_m, z.c_m));
        return d - z.radius_m - c.radius_m;
      }
      return min_along_segment(z, a, b) - c.radius_m;
    }
    case ColliderKind::kBox: return box_collider_distance(z, c);
    case ColliderKind::kCupShell: return cup_collider_distance(z, c);
    default: return bound;  // not an instrument part
  }
}

void evaluate_zones(std::span<const DangerZone> zones, std::span<const Collider> instrument,
                    const Vec3& instrument_force_N, std::span<ZoneSample> out) {
  const double force = instrument_force_N.norm();
  for (std::size_t i = 0; i < zones.size() && i < out.size(); ++i) {
    double d = kInf;
    for (const Collider& c : instrument) d = std::min(d, zone_collider_distance(zones[i], c));
    ZoneSample& s = out[i];
    s.distance_m = d;
    s.inside = d < 0.0;
    s.warning = d < zones[i].warning_distance_m;
    s.force_N = s.warning ? force : 0.0;
  }
}

std::vector<DangerZone> make_c4c5_zones(const SegmentParams& params, const SegmentLandmarks& l,
                                        const SignedDistanceGrid* c4_bone,
                                        const SignedDistanceGrid* c5_bone, const C4C5ZoneParams& zp) {
  std::vector<DangerZone> zones;
  const char* side_name[2] = {"left", "right"};  // +x is the patient's left
  const double y_top = 0.5 * params.disc_height_m + params.c4.body_height_m;
  const double y_bottom = -0.5 * params.disc_height_m - params.c5.body_height_m;

  // Vertebral arteries: vertical through the foramina transversaria of C4 and C5, exposed
  // between the transverse processes at the level of the disc.
  for (int s = 0; s < 2; ++s) {
    DangerZone z;
    z.name = std::string("vertebral_artery_") + side_name[s];
    z.shape = ZoneShape::kCapsule;
    const Vec3 ft = l.foramen_transversarium_m[s];
    z.a_m = Vec3(ft.x(), y_bottom, ft.z());
    z.b_m = Vec3(ft.x(), y_top, ft.z());
    z.radius_m = zp.artery_radius_m;
    z.warning_distance_m = zp.artery_warning_m;
    z.force_limit_N = zp.artery_force_limit_N;
    z.never_event = true;
    zones.push_back(z);
  }
  // Exiting nerve roots: from the dura out through the intervertebral foramina, along the
  // generated root's path (bent where it leaves the canal for the foramen).
  for (int s = 0; s < 2; ++s) {
    DangerZone z;
    z.name = std::string("nerve_root_") + side_name[s];
    z.shape = ZoneShape::kCapsule;
    z.a_m = l.nerve_root_m[s][0];
    z.b_m = l.nerve_root_m[s][1];
    z.c_m = l.nerve_root_m[s][2];
    z.bent = true;
    z.radius_m = zp.root_radius_m;
    z.warning_distance_m = zp.root_warning_m;
    z.force_limit_N = zp.root_force_limit_N;
    z.never_event = true;
    zones.push_back(z);
  }
  // Spinal cord behind the posterior longitudinal ligament: the dural sac filling the canal
  // behind the disc and the bodies, from the back of the disc space to the laminae. Its front
  // is the ligament, flat on the back of the bodies; its edges are rounded by a third of the
  // canal's depth, as the sac rounds into the lateral recesses and under the laminae that
  // close the canal behind (the canal is triangular, not square, in cross-section).
  {
    DangerZone z;
    z.name = "spinal_cord_pll";
    z.shape = ZoneShape::kBox;
    const double z0 = l.canal_back_z_m, z1 = l.body_back_z_m;
    z.a_m = Vec3(0.0, 0.5 * (y_top + y_bottom), 0.5 * (z0 + z1));
    z.half_extents_m = Vec3(l.canal_half_width_m - 1.0e-3, 0.5 * (y_top - y_bottom), 0.5 * (z1 - z0));
    z.radius_m = (z1 - z0) / 3.0;
    z.warning_distance_m = zp.cord_warning_m;
    z.force_limit_N = zp.cord_force_limit_N;
    z.never_event = true;
    zones.push_back(z);
  }
  // Endplates: the bone facing the disc space, within the endplate's outline.
  for (int level = 0; level < 2; ++level) {
    const bool c4 = level == 0;
    const SignedDistanceGrid* bone = c4 ? c4_bone : c5_bone;
    if (bone == nullptr) continue;
    {
      DangerZone z;
      z.name = c4 ? "endplate_c4_lower" : "endplate_c5_upper";
      z.shape = ZoneShape::kSdfBand;
      z.sdf = bone;
      z.band_m = 0.0;
      const double y_plate = c4 ? l.c4_lower_endplate_y_m : l.c5_upper_endplate_y_m;
      const double y_far = y_plate + (c4 ? 1.0 : -1.0) * zp.endplate_depth_m;
      z.region_min_m = Vec3(-l.endplate_half_width_m, std::min(0.0, y_far), l.body_back_z_m);
      z.region_max_m = Vec3(l.endplate_half_width_m, std::max(0.0, y_far), l.body_front_z_m);
      z.warning_distance_m = zp.endplate_warning_m;
      z.force_limit_N = zp.endplate_force_limit_N;
      z.never_event = false;
      zones.push_back(z);
    }
  }
  return zones;
}

}  // namespace acdr
