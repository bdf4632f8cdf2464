// Danger zones: shape distances, instrument-to-zone distances against brute force, the flags
// and forces per step, and the zones generated with the C4-C5 anatomy.
#include "engine/anatomy/danger_zone.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <numbers>

#include "engine/geometry/mesh_shapes.hpp"
#include "tests/support/counting_allocator.hpp"

namespace acdr {
namespace {

constexpr double kMm = 1e-3;

DangerZone capsule_zone(const Vec3& a, const Vec3& b, double r) {
  DangerZone z;
  z.shape = ZoneShape::kCapsule;
  z.a_m = a;
  z.b_m = b;
  z.radius_m = r;
  return z;
}

Collider shaft(const Vec3& from, const Vec3& to, double r) {
  Collider c;
  c.kind = ColliderKind::kCapsule;
  c.pose.position = 0.5 * (from + to);
  c.pose.orientation = Quat::FromTwoVectors(Vec3::UnitZ(), (to - from).normalized());
  c.half_length_m = 0.5 * (to - from).norm();
  c.radius_m = r;
  return c;
}

TEST(DangerZone, SegmentSegmentDistance) {
  // Skew perpendicular lines 2 apart.
  EXPECT_NEAR(segment_segment_distance(Vec3(-1, 0, 0), Vec3(1, 0, 0), Vec3(0, -1, 2), Vec3(0, 1, 2)), 2.0, 1e-12);
  // Parallel, overlapping.
  EXPECT_NEAR(segment_segment_distance(Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(1, 3, 0), Vec3(2, 3, 0)), 3.0, 1e-12);
  // End to end.
  EXPECT_NEAR(segment_segment_distance(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(4, 4, 0), Vec3(5, 5, 0)), 5.0, 1e-12);
  // A point and a segment.
  EXPECT_NEAR(segment_segment_distance(Vec3(0, 2, 0), Vec3(0, 2, 0), Vec3(-1, 0, 0), Vec3(1, 0, 0)), 2.0, 1e-12);
}

TEST(DangerZone, ShapeDistances) {
  DangerZone s;
  s.shape = ZoneShape::kSphere;
  s.a_m = Vec3(1, 0, 0);
  s.radius_m = 0.5;
  EXPECT_NEAR(s.signed_distance(Vec3(3, 0, 0)), 1.5, 1e-12);
  EXPECT_NEAR(s.signed_distance(Vec3(1, 0, 0)), -0.5, 1e-12);
  const DangerZone c = capsule_zone(Vec3(0, 0, 0), Vec3(0, 0, 2), 0.5);
  EXPECT_NEAR(c.signed_distance(Vec3(1, 0, 1)), 0.5, 1e-12);
  EXPECT_NEAR(c.signed_distance(Vec3(0, 0, 3)), 0.5, 1e-12);
  DangerZone b;
  b.shape = ZoneShape::kBox;
  b.a_m = Vec3(0, 0, 0);
  b.half_extents_m = Vec3(1, 2, 3);
  b.orientation = Quat(Eigen::AngleAxisd(0.5 * std::numbers::pi, Vec3::UnitZ()));  // x <-> y
  EXPECT_NEAR(b.signed_distance(Vec3(3, 0, 0)), 1.0, 1e-12);  // the 2 half extent now along x
  EXPECT_NEAR(b.signed_distance(Vec3(0, 0, 0)), -1.0, 1e-12);
}

TEST(DangerZone, BentCapsuleAndRoundedBox) {
  // An L-shaped capsule: along x to the corner, then along y.
  DangerZone c = capsule_zone(Vec3(0, 0, 0), Vec3(2, 0, 0), 0.5);
  c.c_m = Vec3(2, 3, 0);
  c.bent = true;
  EXPECT_NEAR(c.signed_distance(Vec3(1, -1, 0)), 0.5, 1e-12);  // beside the first leg
  EXPECT_NEAR(c.signed_distance(Vec3(3, 2, 0)), 0.5, 1e-12);   // beside the second leg
  EXPECT_NEAR(c.signed_distance(Vec3(0, 3, 0)), 1.5, 1e-12);   // inside the L: nearer the second leg
  c.bent = false;
  EXPECT_NEAR(c.signed_distance(Vec3(3, 2, 0)), std::sqrt(5.0) - 0.5, 1e-12);  // the second leg gone
  // The shaft against each leg is exact: a vertical shaft 1 beside the second leg.
  c.bent = true;
  const Collider v = shaft(Vec3(3.2, 1.5, -5), Vec3(3.2, 1.5, 5), 0.1);
  EXPECT_NEAR(zone_collider_distance(c, v), 1.2 - 0.5 - 0.1, 1e-12);

  // A 4 x 4 x 2 box with its edges rounded by 0.5: the faces stay, the corners recede.
  DangerZone b;
  b.shape = ZoneShape::kBox;
  b.half_extents_m = Vec3(2, 2, 1);
  b.radius_m = 0.5;
  EXPECT_NEAR(b.signed_distance(Vec3(3, 0, 0)), 1.0, 1e-12);  // off a face: as a sharp box
  EXPECT_NEAR(b.signed_distance(Vec3(0, 0, 0)), -1.0, 1e-12);
  const Vec3 corner_dir = Vec3(1, 1, 1).normalized();
  // Off a corner: from the rounded corner's centre (1.5, 1.5, 0.5), minus the rounding.
  const Vec3 p = Vec3(1.5, 1.5, 0.5) + 2.0 * corner_dir;
  EXPECT_NEAR(b.signed_distance(p), 2.0 - 0.5, 1e-12);
  b.radius_m = 0.0;
  EXPECT_NEAR(b.signed_distance(p), (p - Vec3(2, 2, 1)).norm(), 1e-12);
}

TEST(DangerZone, SdfBandIsBoneWithinItsRegion) {
  // "Bone": a 10 mm cube; the zone is its top layer within |x| < 2 mm.
  const TriangleMesh cube = make_box_mesh(Vec3::Constant(-5 * kMm), Vec3::Constant(5 * kMm));
  SdfGridParams gp;
  gp.spacing_m = 0.25 * kMm;
  const SignedDistanceGrid grid = SignedDistanceGrid::build(cube, gp);
  DangerZone z;
  z.shape = ZoneShape::kSdfBand;
  z.sdf = &grid;
  z.region_min_m = Vec3(-2 * kMm, -5 * kMm, 2 * kMm);
  z.region_max_m = Vec3(2 * kMm, 5 * kMm, 8 * kMm);
  EXPECT_NEAR(z.signed_distance(Vec3(0, 0, 6 * kMm)), 1 * kMm, 0.02 * kMm);   // above the plate
  EXPECT_LT(z.signed_distance(Vec3(0, 0, 4.5 * kMm)), 0.0);                   // in the bone layer
  EXPECT_NEAR(z.signed_distance(Vec3(4 * kMm, 0, 6 * kMm)), 2 * kMm, 0.02 * kMm);  // beside the region
  EXPECT_GT(z.signed_distance(Vec3(0, 0, 0)), 1.9 * kMm);                     // bone, below the region
}

TEST(DangerZone, ShaftAgainstCapsuleIsExactAndAgainstBoxMatchesDenseSampling) {
  const Collider c = shaft(Vec3(0, 0, 10 * kMm), Vec3(0, 0, 90 * kMm), 1 * kMm);
  const DangerZone artery = capsule_zone(Vec3(6 * kMm, -20 * kMm, 30 * kMm), Vec3(6 * kMm, 20 * kMm, 30 * kMm), 2 * kMm);
  EXPECT_NEAR(zone_collider_distance(artery, c), 3 * kMm, 1e-12);

  DangerZone box;
  box.shape = ZoneShape::kBox;
  box.a_m = Vec3(5 * kMm, 0, 0);
  box.half_extents_m = Vec3(2 * kMm, 2 * kMm, 2 * kMm);
  box.orientation = Quat(Eigen::AngleAxisd(0.4, Vec3(1, 1, 0).normalized()));
  const Collider tilted = shaft(Vec3(-3 * kMm, 0, -6 * kMm), Vec3(2 * kMm, 1 * kMm, 9 * kMm), 0.8 * kMm);
  double dense = 1e9;
  const Vec3 a = tilted.pose.apply(Vec3(0, 0, -tilted.half_length_m)), b = tilted.pose.apply(Vec3(0, 0, tilted.half_length_m));
  for (int i = 0; i <= 100000; ++i) dense = std::min(dense, box.signed_distance(a + (b - a) * (i / 100000.0)));
  EXPECT_NEAR(zone_collider_distance(box, tilted), dense - 0.8 * kMm, 0.06 * kMm);
}

TEST(DangerZone, BladeAndCupAgainstASphere) {
  DangerZone s;
  s.shape = ZoneShape::kSphere;
  s.a_m = Vec3(0, 0, 0);
  s.radius_m = 1 * kMm;
  // Blade 10 x 6 x 2 mm, its nearest face 3 mm from the sphere centre: 2 mm apart.
  Collider blade;
  blade.kind = ColliderKind::kBox;
  blade.half_extents_m = Vec3(5 * kMm, 3 * kMm, 1 * kMm);
  blade.pose.position = Vec3(0, 0, 4 * kMm);
  EXPECT_NEAR(zone_collider_distance(s, blade), 2 * kMm, 0.02 * kMm);
  // Overlapping by 0.5 mm.
  blade.pose.position = Vec3(0.3 * kMm, 0.2 * kMm, 1.5 * kMm);
  EXPECT_NEAR(zone_collider_distance(s, blade), -0.5 * kMm, 0.01 * kMm);
  // Cup of outer radius 2 mm, its bottom pole 1.5 mm above the sphere.
  Collider cup;
  cup.kind = ColliderKind::kCupShell;
  cup.radius_m = 2 * kMm;
  cup.thickness_m = 0.4 * kMm;
  cup.pose.position = Vec3(0, 0, 4.5 * kMm);
  EXPECT_NEAR(zone_collider_distance(s, cup), 1.5 * kMm, 0.02 * kMm);
  // Upside down (opening toward the sphere): the inner edge of the rim is nearest.
  cup.pose.orientation = Quat(Eigen::AngleAxisd(std::numbers::pi, Vec3::UnitX()));
  cup.pose.position = Vec3(0, 0, 3.5 * kMm);
  EXPECT_NEAR(zone_collider_distance(s, cup), std::hypot(1.6, 3.5) * kMm - 1 * kMm, 0.02 * kMm);
}

TEST(DangerZone, FlagsAndForcePerZoneWithoutAllocation) {
  std::vector<DangerZone> zones = {capsule_zone(Vec3(0, 0, 0), Vec3(0, 10 * kMm, 0), 1 * kMm),
                                   capsule_zone(Vec3(20 * kMm, 0, 0), Vec3(20 * kMm, 10 * kMm, 0), 1 * kMm)};
  zones[0].warning_distance_m = 2 * kMm;
  zones[1].warning_distance_m = 2 * kMm;
  std::vector<Collider> instrument = {shaft(Vec3(2.5 * kMm, 5 * kMm, 0), Vec3(2.5 * kMm, 5 * kMm, 50 * kMm), 0.5 * kMm)};
  std::vector<ZoneSample> out(zones.size());
  const long before = test_support::heap_allocations();
  evaluate_zones(zones, instrument, Vec3(0, 0, 1.5), out);
  EXPECT_EQ(test_support::heap_allocations(), before);
  EXPECT_NEAR(out[0].distance_m, 1 * kMm, 1e-12);
  EXPECT_TRUE(out[0].warning);
  EXPECT_FALSE(out[0].inside);
  EXPECT_DOUBLE_EQ(out[0].force_N, 1.5);
  EXPECT_FALSE(out[1].warning);
  EXPECT_DOUBLE_EQ(out[1].force_N, 0.0);
  instrument[0].pose.position.x() = 0.5 * kMm;
  evaluate_zones(zones, instrument, Vec3::Zero(), out);
  EXPECT_TRUE(out[0].inside);
  EXPECT_LT(out[0].distance_m, 0.0);
}

TEST(DangerZone, GeneratedZonesSitWhereTheAnatomySays) {
  SegmentParams p;
  p.mesh_spacing_m = 0.6e-3;
  const SegmentLandmarks l = segment_landmarks(p);
  SdfGridParams gp;
  gp.spacing_m = 0.4e-3;
  gp.clip = true;
  gp.clip_min_m = Vec3(-12 * kMm, -6 * kMm, -12 * kMm);
  gp.clip_max_m = Vec3(12 * kMm, 6 * kMm, 10 * kMm);
  const SignedDistanceGrid c4 = SignedDistanceGrid::build(generate_vertebra(p, VertebraLevel::kC4), gp);
  const SignedDistanceGrid c5 = SignedDistanceGrid::build(generate_vertebra(p, VertebraLevel::kC5), gp);
  const std::vector<DangerZone> zones = make_c4c5_zones(p, l, &c4, &c5);
  ASSERT_EQ(zones.size(), 7u);
  EXPECT_EQ(zones[0].name, "vertebral_artery_left");
  EXPECT_EQ(zones[4].name, "spinal_cord_pll");
  EXPECT_EQ(zones[6].name, "endplate_c5_upper");

  // A cup curette head (outer radius 1.9 mm) at the centre of the disc space: clear of every
  // zone, about half the disc height from each endplate.
  Collider cup;
  cup.kind = ColliderKind::kCupShell;
  cup.radius_m = 1.9 * kMm;
  cup.thickness_m = 0.4 * kMm;
  cup.pose.position = Vec3(0, -0.5 * kMm, 1 * kMm);  // 0.5 mm nearer C5
  std::vector<ZoneSample> out(zones.size());
  evaluate_zones(zones, std::span<const Collider>(&cup, 1), Vec3::Zero(), out);
  for (std::size_t i = 0; i < zones.size(); ++i) EXPECT_FALSE(out[i].warning) << zones[i].name;
  EXPECT_NEAR(out[5].distance_m, 0.5 * p.disc_height_m + 0.5 * kMm - 1.9 * kMm, 0.05 * kMm);
  EXPECT_NEAR(out[6].distance_m, 0.5 * p.disc_height_m - 0.5 * kMm - 1.9 * kMm, 0.05 * kMm);
  EXPECT_GT(out[0].distance_m, 8 * kMm);  // artery far lateral

  // Pushed to the posterolateral corner of the disc space, next to the uncinate process: the
  // exiting root warns.
  cup.pose.position = Vec3(l.endplate_half_width_m - 2.0 * kMm, 0, l.body_back_z_m + 2.0 * kMm);
  evaluate_zones(zones, std::span<const Collider>(&cup, 1), Vec3(0, 0, 2.0), out);
  EXPECT_TRUE(out[2].warning) << out[2].distance_m;  // nerve_root_left
  EXPECT_FALSE(out[2].inside);
  EXPECT_DOUBLE_EQ(out[2].force_N, 2.0);
  EXPECT_FALSE(out[3].warning);  // the right root is far
  // Slid laterally out of the front of the disc toward the foramen transversarium: the
  // artery warns.
  cup.pose.position = Vec3(l.foramen_transversarium_m[0].x() - 4.0 * kMm, 0, l.foramen_transversarium_m[0].z() + 1.5 * kMm);
  evaluate_zones(zones, std::span<const Collider>(&cup, 1), Vec3::Zero(), out);
  EXPECT_TRUE(out[0].warning) << out[0].distance_m;
  EXPECT_TRUE(zones[0].never_event);
  EXPECT_FALSE(zones[5].never_event);

  // The roots follow the generated path through its three points; the cord zone's front is
  // flat on the back of the bodies behind the disc, and its edges are rounded.
  for (int s = 0; s < 2; ++s) {
    const DangerZone& root = zones[2 + s];
    EXPECT_TRUE(root.bent);
    for (const Vec3& q : l.nerve_root_m[s]) EXPECT_NEAR(root.signed_distance(q), -root.radius_m, 1e-12);
  }
  const DangerZone& cord = zones[4];
  EXPECT_GT(cord.radius_m, 3 * kMm);
  EXPECT_NEAR(cord.signed_distance(Vec3(0, 0, l.body_back_z_m + 1 * kMm)), 1 * kMm, 1e-9);
  EXPECT_NEAR(cord.signed_distance(Vec3(3 * kMm, 0, l.body_back_z_m + 1 * kMm)), 1 * kMm, 1e-9);
  // At the front's lateral corner a sharp box would be 1 mm away; the rounded one is further.
  const Vec3 corner(cord.a_m.x() + cord.half_extents_m.x(), 0, l.body_back_z_m + 1 * kMm);
  EXPECT_GT(cord.signed_distance(corner), 2 * kMm);
}

}  // namespace
}  // namespace acdr
