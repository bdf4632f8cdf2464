// Procedural C4 and C5: a vertebra as a blend of simple solids, meshed by marching tetrahedra.
// Local frame of a vertebra: origin at the centre of its body, axes as the segment frame
// (x left, y cranial, z anterior); the segment places C4 above and C5 below the disc space.
#include "engine/anatomy/vertebra_generator.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "engine/core/disk_cache.hpp"
#include "engine/geometry/iso_surface.hpp"
#include "engine/core/state_hash.hpp"
#include "engine/geometry/sdf_primitives.hpp"

namespace acdr {
namespace {

constexpr double kMm = 1e-3;
// Bump whenever the shape code below changes: cached meshes are keyed by it.
constexpr std::uint32_t kShapeVersion = 2;
constexpr double kBlend = 1.0 * kMm;        // fillet radius where parts meet
constexpr double kJointGap = 0.5 * kMm;     // uncovertebral joint: clearance around the uncinate

/// Everything derived from the parameters that the shape needs, in the local frame.
struct Derived {
  double H, D, e, tu, W2, zb, zf;
  double cw2;          // canal half width
  double r_ft, x_ft, z_ft;
  double disc_above, disc_below;  // disc heights to the neighbours (for facets and bevels)
};

Derived derive(const VertebraParams& v, double disc_above, double disc_below) {
  Derived d;
  d.H = v.body_height_m;
  d.D = v.body_depth_m;
  d.e = 0.5 * v.endplate_width_m;
  d.tu = v.uncinate_thickness_m;
  d.W2 = d.e + d.tu;
  d.zb = -0.5 * d.D;
  d.zf = 0.5 * d.D;
  d.cw2 = 0.5 * v.canal_transverse_m;
  d.r_ft = 0.5 * v.foramen_transversarium_diameter_m;
  // The foramen's medial edge lies `uncinate_to_foramen` lateral to the medial uncinate margin.
  d.x_ft = d.e + v.uncinate_to_foramen_m + d.r_ft;
  d.z_ft = d.zb + v.foramen_anterior_offset_m;
  d.disc_above = disc_above;
  d.disc_below = disc_below;
  return d;
}

/// An uncinate process on side s (+1 / -1), rising from the upper endplate at the
/// posterolateral margin, tapering toward its tip.
double uncinate(const VertebraParams& v, const Derived& d, double s, const Vec3& q) {
  const double uh = v.uncinate_height_m;
  const double y0 = 0.5 * d.H - 1.5 * kMm, y1 = 0.5 * d.H + uh;
  const double z0 = d.zb + 0.3 * kMm, z1 = d.zb + v.uncinate_depth_fraction * d.D;
  const Vec3 c(s * (d.e + 0.5 * d.tu), 0.5 * (y0 + y1), 0.5 * (z0 + z1));
  const Vec3 half(0.5 * d.tu, 0.5 * (y1 - y0), 0.5 * (z1 - z0));
  double u = sdf::box(q, c, half, 0.6 * kMm);
  // Lateral face slopes in so the tip is ~45 % of the base thickness; the medial face (the
  // lateral wall of the disc space) stays vertical.
  const Vec3 n = Vec3(s * uh, 0.55 * d.tu, 0.0).normalized();
  u = sdf::intersect(u, sdf::half_space(q, Vec3(s * d.W2, 0.5 * d.H, 0.0), n));
  // Highest at the back, falling to ~40 % toward its anterior end.
  const Vec3 m = Vec3(0.0, z1 - z0, 0.6 * uh).normalized();
  u = sdf::intersect(u, sdf::half_space(q, Vec3(0.0, y1, z0), m));
  return u;
}

/// Lateral mass (articular pillar) on side s, cut by the facet joint planes above and below.
/// The facets are inclined 45 degrees, the superior facet facing up and back.
double lateral_mass(const Derived& d, double facet_gap, double s, const Vec3& q) {
  const double width = 7.5 * kMm, depth = 8.5 * kMm;
  const double zc = d.zb - 4.0 * kMm - 0.5 * depth;
  const Vec3 c(s * (d.cw2 + 0.3 * kMm + 0.5 * width), 0.0, zc);
  const double y_top = 0.5 * d.H + 0.5 * d.disc_above;
  const double y_bot = -0.5 * d.H - 0.5 * d.disc_below;
  const Vec3 half(0.5 * width, 0.5 * (y_top - y_bot) + 0.5 * depth, 0.5 * depth);
  double m = sdf::box(q, Vec3(c.x(), 0.5 * (y_top + y_bot), zc), half, 3.5 * kMm);
  const Vec3 n = Vec3(0.0, 1.0, -1.0).normalized();
  m = sdf::intersect(m, sdf::half_space(q, Vec3(0, y_top, zc), n) + 0.5 * facet_gap);
  m = sdf::intersect(m, -sdf::half_space(q, Vec3(0, y_bot, zc), n) + 0.5 * facet_gap);
  return m;
}

/// Lamina on side s: a plate from the lateral mass to the midline behind the canal.
double lamina(const VertebraParams& v, const Derived& d, double s, const Vec3& q) {
  const double lt = v.lamina_thickness_m;
  const double z_canal_back = d.zb - v.canal_sagittal_m;
  const Vec3 a(s * (d.cw2 + 1.5 * kMm), 0.0, d.zb - 10.5 * kMm);
  const Vec3 b(0.0, 0.0, z_canal_back - 0.5 * lt);
  const Vec3 ab = b - a;
  const double len = ab.norm();
  Eigen::Matrix3d to_local;
  to_local.row(0) = ab / len;
  to_local.row(1) = Vec3::UnitY();
  to_local.row(2) = Vec3(-ab.z(), 0.0, ab.x()) / len;
  const Vec3 half(0.5 * len + 0.5 * lt, 0.5 * d.H - 1.5 * kMm, 0.5 * lt);
  return sdf::oriented_box(q, 0.5 * (a + b), to_local, half, 0.5 * kMm);
}

/// Bifid spinous process sloping down and back from the laminae.
double spinous(const VertebraParams& v, const Derived& d, const Vec3& q) {
  const double lt = v.lamina_thickness_m;
  const double z0 = d.zb - v.canal_sagittal_m - 0.5 * lt;
  const double z1 = z0 - 0.5 * lt - v.spinous_process_length_m;
  const Vec3 a(0, 0.5 * kMm, z0), b(0, -3.0 * kMm, z1);
  double sp = sdf::capsule(q, a + Vec3(0, 0.8 * kMm, 0), b + Vec3(0, 0.8 * kMm, 0), 1.8 * kMm);
  sp = sdf::smooth_union(sp, sdf::capsule(q, a - Vec3(0, 0.8 * kMm, 0), b - Vec3(0, 0.8 * kMm, 0), 1.8 * kMm), kBlend);
  for (double s : {1.0, -1.0}) {
    sp = sdf::smooth_union(sp, sdf::sphere(q, Vec3(s * 2.3 * kMm, -3.5 * kMm, z1 + 0.6 * kMm), 2.0 * kMm), kBlend);
  }
  return sp;
}

/// Pedicle on side s: an oval bar from the posterolateral body back to the lateral mass.
double pedicle(const VertebraParams& v, const Derived& d, double s, const Vec3& q) {
  const double pw = v.pedicle_width_m, ph = v.pedicle_height_m;
  const double yp = 0.5 * d.H - 0.5 * ph - 1.0 * kMm;  // upper part of the body
  const double x0 = s * (d.cw2 + 0.5 * pw);
  const Vec3 a(x0, yp, d.zb + 1.0 * kMm), b(x0 + s * 1.5 * kMm, yp, d.zb - 4.5 * kMm);
  const Vec3 dy(0, 0.5 * std::max(ph - pw, 0.0), 0);
  return sdf::smooth_union(sdf::capsule(q, a + dy, b + dy, 0.5 * pw),
                           sdf::capsule(q, a - dy, b - dy, 0.5 * pw), kBlend);
}

/// Transverse process on side s: an anterior root (the costal element, from the side of the
/// body) and a posterior root (from the pedicle) that meet lateral to the foramen
/// transversarium in the costotransverse bar, each ending in its tubercle; the bar lies lower
/// than the roots, so their upper faces make the gutter the spinal nerve runs out in. The
/// foramen is cut from the ring afterwards (vertebra_local).
double transverse_process(const VertebraParams& v, const Derived& d, double s, const Vec3& q) {
  const double r = 1.4 * kMm;                    // half the roots' thickness
  const double yt = 0.5 * d.H - 4.0 * kMm;        // level of the roots
  const double x_out = d.x_ft + d.r_ft + v.transverse_process_reach_m;
  const double za = d.z_ft + d.r_ft + 0.9 * kMm;  // anterior root, in front of the foramen
  const double zp = d.z_ft - d.r_ft - 0.9 * kMm;  // posterior root, behind it
  const double x_bar = d.x_ft + d.r_ft + 1.1 * kMm;
  // Flattened bars: two capsules one above the other.
  auto bar = [&](const Vec3& a, const Vec3& b, double rr) {
    const Vec3 dy(0, 0.7 * kMm, 0);
    return sdf::smooth_union(sdf::capsule(q, a + dy, b + dy, rr), sdf::capsule(q, a - dy, b - dy, rr), kBlend);
  };
  double t = bar(Vec3(s * (d.W2 - 1.5 * kMm), yt, za - 0.5 * kMm),
                 Vec3(s * (x_out - 2.0 * kMm), yt - 0.8 * kMm, za + 0.3 * kMm), r);
  t = sdf::smooth_union(t, bar(Vec3(s * (d.cw2 + 0.5 * kMm), yt, zp),
                               Vec3(s * (x_out - 1.8 * kMm), yt - 0.6 * kMm, zp - 0.3 * kMm), r), kBlend);
  t = sdf::smooth_union(t, bar(Vec3(s * x_bar, yt - 1.2 * kMm, za), Vec3(s * x_bar, yt - 1.2 * kMm, zp), 1.1 * kMm), kBlend);
  // Anterior tubercle (the larger, lower one) and posterior tubercle.
  t = sdf::smooth_union(t, sdf::sphere(q, Vec3(s * (x_out - 2.0 * kMm), yt - 1.8 * kMm, za + 0.6 * kMm), 2.0 * kMm), kBlend);
  t = sdf::smooth_union(t, sdf::sphere(q, Vec3(s * (x_out - 1.8 * kMm), yt - 1.0 * kMm, zp - 0.5 * kMm), 1.8 * kMm), kBlend);
  return t;
}

/// 0 at x <= a, 1 at x >= b, smooth between (a < b).
double smoothstep(double a, double b, double x) {
  const double t = std::clamp((x - a) / (b - a), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

/// The body: an oval cross-section (rounded in front, flatter behind), its superior endplate a
/// saddle that rises from the middle toward the uncinate processes, its inferior endplate
/// convex from side to side (it sits in the saddle below) with the anterior lip hanging down
/// in front of the disc.
double body(const VertebraParams& v, const Derived& d, const Vec3& q) {
  const double a = d.W2, b = 0.5 * d.D;
  // Superellipse: exponent 2.4 in front (an oval, rounded anterior face), 6 behind (the
  // posterior wall nearly flat, its corners rounded). ||.||_n <= ||.||_2 for n >= 2, so this
  // stays a distance bound.
  const double n = q.z() > 0.0 ? 2.4 : 6.0;
  const double r = std::pow(std::pow(std::abs(q.x()) / a, n) + std::pow(std::abs(q.z()) / b, n), 1.0 / n);
  const double d2 = (r - 1.0) * std::min(a, b);
  // Transverse saddle of both endplates: the surfaces rise laterally by the concavity.
  const double u = std::min(q.x() * q.x() / (d.e * d.e), 1.0);
  const double rise = v.superior_concavity_m * u;
  const double top = 0.5 * d.H + rise;
  double bottom = -0.5 * d.H + rise;
  // Anterior lip of the inferior endplate: the front rim reaches down, most in the middle,
  // fading toward the sides; resected over the middle when asked.
  const double wl = 0.9 * a, xl = q.x() * q.x() / (wl * wl);
  // Along the front rim: from 3.5 mm inside the oval outline to 1 mm inside it, front half only.
  double lip = q.z() > 0.0 ? v.anterior_lip_m * std::max(0.0, 1.0 - xl * xl) *
                                 smoothstep(-3.5 * kMm, -1.0 * kMm, d2)
                           : 0.0;
  if (v.lip_resection_width_m > 0.0) {
    const double w = 0.5 * v.lip_resection_width_m;
    lip *= smoothstep(w, w + 1.0 * kMm, std::abs(q.x()));
  }
  bottom -= lip;
  const double mid = 0.5 * (top + bottom), half = 0.5 * (top - bottom);
  // The sloping faces steepen the function by up to ~1.5: scale it back to a distance bound.
  return sdf::extrude(d2, q.y() - mid, half, 0.8 * kMm) / 1.6;
}

/// The whole vertebra in its local frame. `below` is the vertebra under it (for the bevel that
/// receives the lower neighbour's uncinate processes), with the disc height between them.
double vertebra_local(const VertebraParams& v, const Derived& d, const VertebraParams& below,
                      const Derived& db, double facet_gap, const Vec3& q) {
  double f = body(v, d, q);
  for (double s : {1.0, -1.0}) {
    f = sdf::smooth_union(f, uncinate(v, d, s, q), 0.8 * kMm);
    f = sdf::smooth_union(f, pedicle(v, d, s, q), kBlend);
    f = sdf::smooth_union(f, transverse_process(v, d, s, q), kBlend);
    f = sdf::smooth_union(f, lateral_mass(d, facet_gap, s, q), kBlend);
    f = sdf::smooth_union(f, lamina(v, d, s, q), kBlend);
  }
  f = sdf::smooth_union(f, spinous(v, d, q), kBlend);
  for (double s : {1.0, -1.0}) {
    // Foramen transversarium: a vertical hole for the vertebral artery.
    f = sdf::smooth_subtract(f, sdf::cylinder(q, Vec3(s * d.x_ft, 0, d.z_ft), Vec3::UnitY(), d.r_ft),
                             0.3 * kMm);
    // Bevel of the inferolateral body edge where the lower neighbour's uncinate sits.
    const Vec3 qb = q + Vec3(0, 0.5 * d.H + d.disc_below + 0.5 * db.H, 0);
    f = sdf::subtract(f, uncinate(below, db, s, qb) - kJointGap);
  }
  return f;
}

}  // namespace

const char* vertebra_level_name(VertebraLevel level) {
  return level == VertebraLevel::kC4 ? "C4" : "C5";
}

Vec3 vertebra_center(const SegmentParams& p, VertebraLevel level) {
  if (level == VertebraLevel::kC4) return Vec3(0, 0.5 * (p.disc_height_m + p.c4.body_height_m), 0);
  return Vec3(0, -0.5 * (p.disc_height_m + p.c5.body_height_m), 0);
}

double vertebra_implicit(const SegmentParams& p, VertebraLevel level, const Vec3& x) {
  // The outer neighbours (C3 above C4, C6 below C5) are not modelled; their discs and the
  // vertebra under C5 take the same sizes, so both levels get the same facets and bevels.
  const bool c4 = level == VertebraLevel::kC4;
  const VertebraParams& v = c4 ? p.c4 : p.c5;
  const VertebraParams& below = p.c5;  // C5 under C4; C5 itself stands in for C6
  const Derived d = derive(v, p.disc_height_m, p.disc_height_m);
  const Derived db = derive(below, p.disc_height_m, p.disc_height_m);
  return vertebra_local(v, d, below, db, p.facet_gap_m, x - vertebra_center(p, level));
}

SegmentLandmarks segment_landmarks(const SegmentParams& p) {
  SegmentLandmarks l;
  const Derived d4 = derive(p.c4, p.disc_height_m, p.disc_height_m);
  const Derived d5 = derive(p.c5, p.disc_height_m, p.disc_height_m);
  const double h = p.disc_height_m;
  l.c4_lower_endplate_y_m = 0.5 * h;
  l.c5_upper_endplate_y_m = -0.5 * h;
  // The disc space is bounded laterally by C5's uncinate processes.
  l.endplate_half_width_m = d5.e;
  l.body_half_width_m = std::min(d4.W2, d5.W2);
  l.body_front_z_m = std::min(d4.zf, d5.zf);
  l.body_back_z_m = std::max(d4.zb, d5.zb);
  l.uncinate_front_z_m = d5.zb + p.c5.uncinate_depth_fraction * d5.D;
  l.canal_back_z_m = std::max(d4.zb - p.c4.canal_sagittal_m, d5.zb - p.c5.canal_sagittal_m);
  l.canal_half_width_m = std::min(d4.cw2, d5.cw2);
  l.foramen_radius_m = 0.5 * (d4.r_ft + d5.r_ft);
  const double x_ft = 0.5 * (d4.x_ft + d5.x_ft), z_ft = 0.5 * (d4.z_ft + d5.z_ft);
  const double zb = l.body_back_z_m, cw2 = l.canal_half_width_m;
  for (int i = 0; i < 2; ++i) {
    const double s = i == 0 ? 1.0 : -1.0;
    l.foramen_transversarium_m[i] = Vec3(s * x_ft, 0.0, z_ft);
    // The root leaves the dura at the front of the canal, slightly above the disc, runs out
    // through the intervertebral foramen between the C4 and C5 pedicles in front of the facet
    // joint, and passes behind the vertebral artery (its tip 1.3-2.0 mm from the posterior
    // uncinate tip, Kim 2012).
    l.nerve_root_m[i] = {Vec3(s * (cw2 - 3.7 * kMm), 1.5 * kMm, zb - 2.5 * kMm),
                         Vec3(s * (cw2 + 1.3 * kMm), 0.5 * kMm, zb - 1.5 * kMm),
                         Vec3(s * (x_ft + l.foramen_radius_m + 1.0 * kMm), -1.5 * kMm,
                              z_ft - l.foramen_radius_m - 1.3 * kMm)};
    l.uncinate_posterior_tip_m[i] =
        Vec3(s * (d5.e + 0.35 * d5.tu), -0.5 * h + p.c5.uncinate_height_m, d5.zb + 0.5 * kMm);
  }
  return l;
}

std::vector<PartPoint> segment_part_points(const SegmentParams& p, double side) {
  const double s = side < 0.0 ? -1.0 : 1.0;
  std::vector<PartPoint> parts;
  for (int b = 0; b < 2; ++b) {
    const VertebraLevel level = b == 0 ? VertebraLevel::kC4 : VertebraLevel::kC5;
    const VertebraParams& v = b == 0 ? p.c4 : p.c5;
    const Derived d = derive(v, p.disc_height_m, p.disc_height_m);
    const Vec3 c = vertebra_center(p, level);
    const std::string n = vertebra_level_name(level);
    auto add = [&](const std::string& name, const Vec3& local) { parts.push_back({n + " " + name, c + local, b}); };
    add("vertebral body", Vec3(0.0, 0.0, d.zf - 1.0 * kMm));
    add("uncinate process", Vec3(s * (d.e + 0.5 * d.tu), 0.5 * d.H + 0.45 * v.uncinate_height_m,
                                 d.zb + 0.3 * v.uncinate_depth_fraction * d.D));
    add("superior endplate (saddle)", Vec3(s * 0.55 * d.e, 0.5 * d.H + 0.3 * v.superior_concavity_m - 0.3 * kMm, 0.0));
    const double x_lip = std::max(0.25 * d.W2, 0.5 * v.lip_resection_width_m + 1.0 * kMm);
    // The front of the oval at that x (exponent 2.4, body()), 1.2 mm behind it.
    const double z_rim = 0.5 * d.D * std::pow(1.0 - std::pow(x_lip / d.W2, 2.4), 1.0 / 2.4) - 1.2 * kMm;
    add("anterior lip", Vec3(s * x_lip, -0.5 * d.H - 0.15 * v.anterior_lip_m, z_rim));
    add("pedicle", Vec3(s * (d.cw2 + 0.5 * v.pedicle_width_m), 0.5 * d.H - 0.5 * v.pedicle_height_m - 1.0 * kMm,
                        d.zb - 2.0 * kMm));
    const double yt = 0.5 * d.H - 4.0 * kMm;
    const double x_out = d.x_ft + d.r_ft + v.transverse_process_reach_m;
    add("anterior tubercle", Vec3(s * (x_out - 2.0 * kMm), yt - 1.8 * kMm, d.z_ft + d.r_ft + 1.5 * kMm));
    add("posterior tubercle", Vec3(s * (x_out - 1.8 * kMm), yt - 1.0 * kMm, d.z_ft - d.r_ft - 1.4 * kMm));
    add("foramen transversarium", Vec3(s * d.x_ft, yt, d.z_ft));
    const double zc_mass = d.zb - 9.0 * kMm;
    add("lateral mass", Vec3(s * (d.cw2 + 4.3 * kMm), 0.0, zc_mass));
    const Vec3 la(s * (d.cw2 + 1.5 * kMm), 0.0, d.zb - 10.5 * kMm);
    const Vec3 lb(0.0, 0.0, d.zb - v.canal_sagittal_m - 0.5 * v.lamina_thickness_m);
    add("lamina", 0.5 * (la + lb));
    const double z0 = d.zb - v.canal_sagittal_m - 0.5 * v.lamina_thickness_m;
    const double z1 = z0 - 0.5 * v.lamina_thickness_m - v.spinous_process_length_m;
    add("spinous process (bifid)", Vec3(s * 2.3 * kMm, -3.5 * kMm, z1 + 0.6 * kMm));
  }
  const SegmentLandmarks l = segment_landmarks(p);
  const Derived d5 = derive(p.c5, p.disc_height_m, p.disc_height_m);
  // The facet joint: between C4's inferior and C5's superior articular facet, at disc level.
  parts.push_back({"facet joint", Vec3(s * (d5.cw2 + 4.3 * kMm), 0.0, d5.zb - 9.0 * kMm + 0.5 * kMm), -1});
  parts.push_back({"spinal canal", Vec3(0.0, 0.0, 0.5 * (l.body_back_z_m + l.canal_back_z_m)), -1});
  return parts;
}

namespace {

/// The box the implicit solid is sampled over: generous enough that the solid is positive on
/// the grid boundary.
void sample_bounds(const SegmentParams& p, VertebraLevel level, Vec3* lo, Vec3* hi) {
  const VertebraParams& v = level == VertebraLevel::kC4 ? p.c4 : p.c5;
  const Derived d = derive(v, p.disc_height_m, p.disc_height_m);
  const double x = d.x_ft + d.r_ft + v.transverse_process_reach_m + 4.0 * kMm;
  const double y = 0.5 * d.H + std::max(v.uncinate_height_m, p.disc_height_m) + 7.0 * kMm;
  const double z_back = d.zb - v.canal_sagittal_m - 2.0 * v.lamina_thickness_m -
                        v.spinous_process_length_m - 6.0 * kMm;
  const Vec3 c = vertebra_center(p, level);
  *lo = c + Vec3(-x, -y, z_back);
  *hi = c + Vec3(x, y, d.zf + 2.0 * kMm);
}

}  // namespace

double vertebra_grid_samples(const SegmentParams& p, VertebraLevel level) {
  Vec3 lo, hi;
  sample_bounds(p, level, &lo, &hi);
  double n = 1.0;
  for (int a = 0; a < 3; ++a) n *= std::ceil(std::max(0.0, hi[a] - lo[a]) / p.mesh_spacing_m) + 1.0;
  return n;
}

TriangleMesh generate_vertebra(const SegmentParams& p, VertebraLevel level,
                               VertebraMeshStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  Vec3 lo, hi;
  sample_bounds(p, level, &lo, &hi);
  const ScalarGrid grid = sample_function(
      [&](const Vec3& q) { return vertebra_implicit(p, level, q); }, lo, hi, p.mesh_spacing_m,
      /*lipschitz=*/true);
  TriangleMesh mesh = extract_iso_surface(grid);
  if (stats) {
    stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stats->samples = grid.values.size();
    stats->triangles = mesh.triangle_count();
    stats->volume_m3 = mesh.signed_volume();
  }
  return mesh;
}

TriangleMesh load_or_generate_vertebra(const SegmentParams& p, VertebraLevel level,
                                       const std::string& cache_dir, VertebraMeshStats* stats,
                                       bool* from_cache) {
  const auto start = std::chrono::steady_clock::now();
  if (from_cache) *from_cache = false;
  // The parameter structs hold doubles only, so their bytes are their values.
  static_assert(sizeof(VertebraParams) % sizeof(double) == 0 && sizeof(SegmentParams) % sizeof(double) == 0);
  std::uint64_t key = fnv1a(&kShapeVersion, sizeof kShapeVersion);
  key = fnv1a(&p, sizeof p, key);
  const int lv = static_cast<int>(level);
  key = fnv1a(&lv, sizeof lv, key);
  const std::string path = cache_dir.empty() ? "" : cache_file_path(cache_dir, key, ".mesh");
  if (!path.empty()) {
    if (const auto bytes = read_cache_file(path)) {
      if (auto mesh = TriangleMesh::deserialize(*bytes, nullptr)) {
        if (from_cache) *from_cache = true;
        if (stats) {
          stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          stats->samples = 0;
          stats->triangles = mesh->triangle_count();
          stats->volume_m3 = mesh->signed_volume();
        }
        return std::move(*mesh);
      }
    }
  }
  TriangleMesh mesh = generate_vertebra(p, level, stats);
  if (!path.empty()) write_cache_file(path, mesh.serialize(), nullptr);  // a cache miss next time at worst
  return mesh;
}

std::string validate_segment_params(const SegmentParams& p) {
  std::ostringstream out;
  auto check = [&](bool ok, const std::string& key, double value_m, const std::string& expected) {
    if (!ok) out << key << ": got " << value_m * 1e3 << " mm, expected " << expected << "\n";
  };
  for (int i = 0; i < 2; ++i) {
    const VertebraParams& v = i == 0 ? p.c4 : p.c5;
    const std::string n = i == 0 ? "c4." : "c5.";
    check(v.endplate_width_m >= 5e-3 && v.endplate_width_m <= 40e-3, n + "endplate_width", v.endplate_width_m, "5 to 40 mm");
    check(v.body_depth_m >= 5e-3 && v.body_depth_m <= 40e-3, n + "body_depth", v.body_depth_m, "5 to 40 mm");
    check(v.body_height_m >= 5e-3 && v.body_height_m <= 30e-3, n + "body_height", v.body_height_m, "5 to 30 mm");
    check(v.uncinate_height_m > 0 && v.uncinate_height_m <= v.body_height_m, n + "uncinate_height", v.uncinate_height_m, "> 0 and at most the body height");
    check(v.uncinate_thickness_m >= 0.5e-3 && v.uncinate_thickness_m <= 0.25 * v.endplate_width_m, n + "uncinate_thickness", v.uncinate_thickness_m, "0.5 mm to a quarter of the endplate width");
    if (!(v.uncinate_depth_fraction >= 0.1 && v.uncinate_depth_fraction <= 1.0)) {
      out << n << "uncinate_depth_fraction: got " << v.uncinate_depth_fraction << ", expected 0.1 to 1\n";
    }
    check(v.pedicle_width_m >= 1e-3 && v.pedicle_width_m <= 15e-3, n + "pedicle_width", v.pedicle_width_m, "1 to 15 mm");
    check(v.pedicle_height_m >= v.pedicle_width_m && v.pedicle_height_m <= v.body_height_m, n + "pedicle_height", v.pedicle_height_m, "at least the pedicle width, at most the body height");
    check(v.canal_sagittal_m >= 5e-3 && v.canal_sagittal_m <= 30e-3, n + "canal_sagittal", v.canal_sagittal_m, "5 to 30 mm");
    // The pedicles stand at the canal's sides: it cannot be narrower than the body minus them.
    check(v.canal_transverse_m >= 10e-3 && v.canal_transverse_m <= 40e-3, n + "canal_transverse", v.canal_transverse_m, "10 to 40 mm");
    check(v.foramen_transversarium_diameter_m >= 1e-3 && v.foramen_transversarium_diameter_m <= 12e-3, n + "foramen_transversarium_diameter", v.foramen_transversarium_diameter_m, "1 to 12 mm");
    // The foramen must lie outside the uncinate process, with bone between them.
    check(v.uncinate_to_foramen_m >= v.uncinate_thickness_m + 0.5e-3 && v.uncinate_to_foramen_m <= 20e-3, n + "uncinate_to_foramen", v.uncinate_to_foramen_m, "at least the uncinate thickness + 0.5 mm, at most 20 mm");
    check(v.foramen_anterior_offset_m >= 0.0 && v.foramen_anterior_offset_m <= v.body_depth_m, n + "foramen_anterior_offset", v.foramen_anterior_offset_m, "0 to the body depth");
    check(v.transverse_process_reach_m >= 1e-3 && v.transverse_process_reach_m <= 20e-3, n + "transverse_process_reach", v.transverse_process_reach_m, "1 to 20 mm");
    check(v.lamina_thickness_m >= 1e-3 && v.lamina_thickness_m <= 8e-3, n + "lamina_thickness", v.lamina_thickness_m, "1 to 8 mm");
    check(v.superior_concavity_m >= 0.0 && v.superior_concavity_m <= 0.5 * v.uncinate_height_m, n + "superior_concavity", v.superior_concavity_m, "0 to half the uncinate height");
    check(v.anterior_lip_m >= 0.0 && v.anterior_lip_m <= 0.5 * p.disc_height_m, n + "anterior_lip", v.anterior_lip_m, "0 to half the disc height");
    check(v.lip_resection_width_m >= 0.0 && v.lip_resection_width_m <= 2.0 * (0.5 * v.endplate_width_m + v.uncinate_thickness_m), n + "lip_resection_width", v.lip_resection_width_m, "0 to the body width");
    check(v.spinous_process_length_m >= 2e-3 && v.spinous_process_length_m <= 40e-3, n + "spinous_process_length", v.spinous_process_length_m, "2 to 40 mm");
  }
  check(p.disc_height_m >= 2e-3 && p.disc_height_m <= 15e-3, "disc_height", p.disc_height_m, "2 to 15 mm");
  check(p.facet_gap_m >= 0.2e-3 && p.facet_gap_m <= 5e-3, "facet_gap", p.facet_gap_m, "0.2 to 5 mm");
  check(p.mesh_spacing_m >= 0.1e-3 && p.mesh_spacing_m <= 2e-3, "mesh_spacing", p.mesh_spacing_m, "0.1 to 2 mm");
  return out.str();
}

}  // namespace acdr
