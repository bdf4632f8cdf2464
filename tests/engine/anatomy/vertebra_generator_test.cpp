// Procedural C4-C5: closed meshes, an empty disc space between the endplates, open foramina
// and canal, and the published distances between landmarks.
#include "engine/anatomy/vertebra_generator.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "engine/geometry/sdf_primitives.hpp"

namespace acdr {
namespace {

constexpr double kMm = 1e-3;

double bone(const SegmentParams& p, const Vec3& x) {
  return std::min(vertebra_implicit(p, VertebraLevel::kC4, x),
                  vertebra_implicit(p, VertebraLevel::kC5, x));
}

TEST(VertebraGenerator, BothVertebraeAreClosedSolids) {
  SegmentParams p;
  p.mesh_spacing_m = 0.8e-3;  // coarse for test speed; the default is finer
  for (VertebraLevel level : {VertebraLevel::kC4, VertebraLevel::kC5}) {
    VertebraMeshStats stats;
    const TriangleMesh m = generate_vertebra(p, level, &stats);
    const MeshCheck c = check_closed_mesh(m);
    EXPECT_TRUE(c.ok) << vertebra_level_name(level) << ": " << c.error;
    // A cervical vertebra holds a few cm^3 of bone.
    EXPECT_GT(c.volume_m3, 4e-6) << vertebra_level_name(level);
    EXPECT_LT(c.volume_m3, 15e-6) << vertebra_level_name(level);
    EXPECT_EQ(stats.triangles, m.triangle_count());
    // C4 lies above the disc space and C5 below it, apart from the uncinate processes of C5
    // which rise beside the disc.
    Vec3 lo, hi;
    m.bounds(&lo, &hi);
    if (level == VertebraLevel::kC4) {
      EXPECT_GT(lo.y(), -0.5 * p.disc_height_m - 12 * kMm);
    }
    if (level == VertebraLevel::kC5) {
      EXPECT_LT(hi.y(), 0.5 * p.disc_height_m + 12 * kMm);
    }
  }
}

TEST(VertebraGenerator, DiscSpaceIsEmptyBetweenBonyEndplates) {
  // With C4's anterior lip taken off over the middle, as the modules have it.
  SegmentParams p;
  p.c4.lip_resection_width_m = 10e-3;
  const SegmentLandmarks l = segment_landmarks(p);
  EXPECT_DOUBLE_EQ(l.c4_lower_endplate_y_m - l.c5_upper_endplate_y_m, p.disc_height_m);
  const double e = l.endplate_half_width_m;
  for (double x : {-e + 1.5 * kMm, 0.0, e - 1.5 * kMm}) {
    // The saddle: both endplates rise from the middle toward the uncinate processes.
    const double rise = p.c5.superior_concavity_m * x * x / (e * e);
    for (double z : {l.body_back_z_m + 1.5 * kMm, 0.0, l.body_front_z_m - 1.5 * kMm}) {
      if (std::abs(x) > 4.0 * kMm && z > 0.0) continue;  // the lip beside the resection
      // Inside the disc space: no bone.
      for (double y : {-0.4, 0.0, 0.4}) EXPECT_GT(bone(p, Vec3(x, y * p.disc_height_m + rise, z)), 0.0);
      // Just past each endplate: bone of C4 above, C5 below.
      EXPECT_LT(vertebra_implicit(p, VertebraLevel::kC4, Vec3(x, l.c4_lower_endplate_y_m + rise + 0.5 * kMm, z)), 0.0);
      EXPECT_LT(vertebra_implicit(p, VertebraLevel::kC5, Vec3(x, l.c5_upper_endplate_y_m + rise - 0.5 * kMm, z)), 0.0);
    }
  }
  // The superior endplate is a saddle: C5's surface stands higher toward the uncinate
  // processes than in the middle, by the concavity.
  auto c5_surface_y = [&](double x) {
    double y = l.c5_upper_endplate_y_m - 2 * kMm;
    while (vertebra_implicit(p, VertebraLevel::kC5, Vec3(x, y, 0.0)) < 0.0) y += 0.01 * kMm;
    return y;
  };
  EXPECT_NEAR(c5_surface_y(0.0), l.c5_upper_endplate_y_m, 0.05 * kMm);
  EXPECT_NEAR(c5_surface_y(0.75 * e) - c5_surface_y(0.0), 0.5625 * p.c5.superior_concavity_m, 0.1 * kMm);
  // The uncinate processes of C5 wall the disc space laterally at its back.
  const double z_unc = l.body_back_z_m + 2 * kMm;
  EXPECT_LT(vertebra_implicit(p, VertebraLevel::kC5, Vec3(e + 0.8 * kMm, 0.0, z_unc)), 0.0);
  EXPECT_LT(vertebra_implicit(p, VertebraLevel::kC5, Vec3(-e - 0.8 * kMm, 0.0, z_unc)), 0.0);
}

TEST(VertebraGenerator, AnteriorLipHangsInFrontOfTheDiscUnlessResected) {
  SegmentParams p;
  const SegmentLandmarks l = segment_landmarks(p);
  // Intact: C4's front rim reaches below its endplate, in front of the disc.
  const Vec3 below_rim(0.0, l.c4_lower_endplate_y_m - 0.8 * p.c4.anterior_lip_m, l.body_front_z_m - 0.8 * kMm);
  EXPECT_LT(vertebra_implicit(p, VertebraLevel::kC4, below_rim), 0.0);
  // ... not behind the rim, where the disc is.
  EXPECT_GT(vertebra_implicit(p, VertebraLevel::kC4, Vec3(0.0, below_rim.y(), 0.0)), 0.0);
  // Resected over the middle: open there, still present beside the resection.
  p.c4.lip_resection_width_m = 10e-3;
  EXPECT_GT(vertebra_implicit(p, VertebraLevel::kC4, below_rim), 0.0);
  for (const PartPoint& part : segment_part_points(p, 1.0))
    if (part.name == "C4 anterior lip") {
      EXPECT_GT(part.point_m.x(), 5.0 * kMm);
      EXPECT_LT(part.point_m.y(), l.c4_lower_endplate_y_m);
      EXPECT_LT(vertebra_implicit(p, VertebraLevel::kC4, part.point_m), 0.0);
    }
}

TEST(VertebraGenerator, EveryNamedPartIsBoneOrInItsOpening) {
  // The label points: bone parts inside their vertebra (within a little of its surface), the
  // foramen transversarium and the canal open.
  SegmentParams p;
  p.c4.lip_resection_width_m = 10e-3;
  for (double side : {-1.0, 1.0}) {
    for (const PartPoint& part : segment_part_points(p, side)) {
      const bool opening = part.name.find("foramen") != std::string::npos ||
                           part.name.find("canal") != std::string::npos;
      if (part.bone < 0 && part.name != "facet joint") {
        EXPECT_GT(bone(p, part.point_m), 0.0) << part.name;
        continue;
      }
      if (part.name == "facet joint") {
        // Between the two lateral masses: close to both.
        EXPECT_LT(std::abs(bone(p, part.point_m)), 1.5 * kMm) << part.name;
        continue;
      }
      const VertebraLevel level = part.bone == 0 ? VertebraLevel::kC4 : VertebraLevel::kC5;
      const double f = vertebra_implicit(p, level, part.point_m);
      if (opening)
        EXPECT_GT(f, 0.0) << part.name;
      else
        EXPECT_LT(f, 0.3 * kMm) << part.name << " at " << format_point_mm(part.point_m);
    }
  }
}

TEST(VertebraGenerator, ForaminaAndCanalAreOpen) {
  const SegmentParams p;
  const SegmentLandmarks l = segment_landmarks(p);
  // Foramen transversarium: medial edge 5.0 mm lateral to the medial uncinate margin
  // (Anat Res Int 2015), open through both transverse processes.
  for (int side = 0; side < 2; ++side) {
    const Vec3 ft = l.foramen_transversarium_m[side];
    EXPECT_NEAR(std::abs(ft.x()) - l.foramen_radius_m - l.endplate_half_width_m, 5.0 * kMm, 1e-12);
    for (VertebraLevel level : {VertebraLevel::kC4, VertebraLevel::kC5}) {
      const Vec3 c = vertebra_center(p, level);
      const double y_tp = c.y() + 0.5 * p.c4.body_height_m - 4.0 * kMm;  // transverse process level
      EXPECT_GT(vertebra_implicit(p, level, Vec3(ft.x(), y_tp, ft.z())), 0.0);
      // ... and ringed by bone: in front of and behind the hole.
      EXPECT_LT(vertebra_implicit(p, level, Vec3(ft.x(), y_tp, ft.z() + l.foramen_radius_m + 1.2 * kMm)), 0.0);
      EXPECT_LT(vertebra_implicit(p, level, Vec3(ft.x(), y_tp, ft.z() - l.foramen_radius_m - 1.2 * kMm)), 0.0);
      // Spinal canal: empty at its centre, at every height of the vertebra.
      const double zc = 0.5 * (l.body_back_z_m + l.canal_back_z_m);
      for (double dy : {-5.0, 0.0, 5.0}) {
        EXPECT_GT(vertebra_implicit(p, level, Vec3(0, c.y() + dy * kMm, zc)), 0.0);
        EXPECT_GT(vertebra_implicit(p, level, Vec3(0.4 * p.c4.canal_transverse_m, c.y() + dy * kMm, zc)), 0.0);
      }
    }
    // The nerve root runs through the intervertebral foramen, clear of bone, and passes
    // 1.3-2.0 mm from the posterior uncinate tip (Kim 2012) for a 3 mm root.
    const auto& root = l.nerve_root_m[side];
    const double to_tip = std::min(sdf::segment_distance(l.uncinate_posterior_tip_m[side], root[0], root[1]),
                                   sdf::segment_distance(l.uncinate_posterior_tip_m[side], root[1], root[2])) -
                          1.5 * kMm;
    EXPECT_GT(to_tip, 1.0 * kMm);
    EXPECT_LT(to_tip, 2.5 * kMm);
    for (double t : {0.0, 0.5, 1.0}) {
      EXPECT_GT(bone(p, root[1] + t * (root[2] - root[1])), 1.0 * kMm) << "root point " << t;
    }
  }
}

TEST(VertebraGenerator, ImplicitSolidIsOneLipschitz) {
  // Coarse-to-fine sampling (iso_surface.hpp) is exact only if f changes no faster than the
  // distance moved.
  const SegmentParams p;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-30e-3, 30e-3), step(-1e-3, 1e-3);
  for (int i = 0; i < 20000; ++i) {
    const Vec3 a(u(rng), u(rng), u(rng)), b = a + Vec3(step(rng), step(rng), step(rng));
    for (VertebraLevel level : {VertebraLevel::kC4, VertebraLevel::kC5}) {
      ASSERT_LE(std::abs(vertebra_implicit(p, level, a) - vertebra_implicit(p, level, b)),
                (a - b).norm() * (1 + 1e-9))
          << "at " << format_point_mm(a);
    }
  }
}

TEST(VertebraGenerator, ParameterChecksNameTheKey) {
  SegmentParams p;
  EXPECT_EQ(validate_segment_params(p), "");
  p.c5.uncinate_to_foramen_m = 1e-3;  // the foramen would cut into the uncinate process
  p.disc_height_m = 30e-3;
  const std::string e = validate_segment_params(p);
  EXPECT_NE(e.find("c5.uncinate_to_foramen: got 1 mm"), std::string::npos) << e;
  EXPECT_NE(e.find("disc_height: got 30 mm, expected 2 to 15 mm"), std::string::npos) << e;
}

TEST(VertebraGenerator, SmallerSpineScalesTheMesh) {
  SegmentParams small;
  small.mesh_spacing_m = 0.8e-3;
  for (VertebraParams* v : {&small.c4, &small.c5}) {
    v->endplate_width_m = 13e-3;
    v->body_depth_m = 13e-3;
    v->body_height_m = 11e-3;
  }
  SegmentParams normal;
  normal.mesh_spacing_m = 0.8e-3;
  const double v_small = generate_vertebra(small, VertebraLevel::kC5).signed_volume();
  const double v_normal = generate_vertebra(normal, VertebraLevel::kC5).signed_volume();
  EXPECT_LT(v_small, 0.9 * v_normal);
  EXPECT_TRUE(check_closed_mesh(generate_vertebra(small, VertebraLevel::kC4)).ok);
}

TEST(VertebraGenerator, SecondStartLoadsTheMeshFromTheCache) {
  const auto dir = (std::filesystem::temp_directory_path() / "acdr_vertebra_cache_test").string();
  std::filesystem::remove_all(dir);
  SegmentParams p;
  p.mesh_spacing_m = 0.9e-3;
  bool cached = true;
  VertebraMeshStats first, second;
  const TriangleMesh a = load_or_generate_vertebra(p, VertebraLevel::kC5, dir, &first, &cached);
  EXPECT_FALSE(cached);
  const TriangleMesh b = load_or_generate_vertebra(p, VertebraLevel::kC5, dir, &second, &cached);
  EXPECT_TRUE(cached);
  EXPECT_EQ(a.content_hash(), b.content_hash());
  EXPECT_EQ(second.triangles, a.triangle_count());
  // Another level or other parameters are other entries.
  load_or_generate_vertebra(p, VertebraLevel::kC4, dir, nullptr, &cached);
  EXPECT_FALSE(cached);
  p.disc_height_m = 5.0e-3;
  load_or_generate_vertebra(p, VertebraLevel::kC5, dir, nullptr, &cached);
  EXPECT_FALSE(cached);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace acdr
