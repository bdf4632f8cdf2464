// The anatomical scene: built from procedural or loaded meshes, cached, with its bone collider
// and zones; a World built with it steps with bone contact and per-zone samples.
#include "engine/anatomy/anatomy.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "engine/geometry/mesh_io.hpp"
#include "engine/world/world.hpp"
#include "tests/engine/anatomy/coarse_segment_scene.hpp"

namespace acdr {
namespace {

constexpr double kMm = 1e-3;

/// A coarse anatomy that builds in well under a second.
AnatomyConfig coarse(const std::string& cache_dir) { return test::coarse_anatomy(cache_dir); }

class AnatomyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // One directory per test and process: ctest -j runs these tests at the same time, and one
    // test's TearDown removing a shared directory broke the other's files.
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = (std::filesystem::temp_directory_path() /
            ("acdr_anatomy_test_" + std::string(info->name()) + "_" + std::to_string(::getpid())))
               .string();
    std::filesystem::remove_all(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string dir_;
};

TEST_F(AnatomyTest, BuildsOnceThenLoadsFromTheCache) {
  const Anatomy first(coarse(dir_));
  EXPECT_FALSE(first.report().meshes_from_cache);
  EXPECT_FALSE(first.report().sdf_from_cache);
  EXPECT_EQ(first.zones().size(), 7u);
  const Anatomy second(coarse(dir_));
  EXPECT_TRUE(second.report().meshes_from_cache);
  EXPECT_TRUE(second.report().sdf_from_cache) << second.report().notes;
  EXPECT_EQ(first.vertebra(VertebraLevel::kC4).content_hash(), second.vertebra(VertebraLevel::kC4).content_hash());
  // The bone collider: the disc space is free, the endplates are where the landmarks say.
  const Collider bone = second.bone_collider();
  EXPECT_EQ(bone.kind, ColliderKind::kSdfGrid);
  Vec3 n;
  const double d = signed_distance(bone, Vec3(0, 1.0 * kMm, 0), &n);
  EXPECT_NEAR(d, second.landmarks().c4_lower_endplate_y_m - 1.0 * kMm, 0.05 * kMm);
  EXPECT_LT(n.y(), -0.95);  // out of the C4 endplate, down into the disc space
  EXPECT_LT(signed_distance(bone, Vec3(0, 5 * kMm, 0), nullptr), 0.0);
}

TEST_F(AnatomyTest, LoadedMeshesGiveTheSameSceneFromObjAndStl) {
  // Export the generated vertebrae, once as OBJ and once as binary STL, in millimetres.
  const Anatomy generated(coarse(dir_));
  std::string error;
  const std::string c4_obj = dir_ + "/c4.obj", c5_obj = dir_ + "/c5.obj";
  const std::string c4_stl = dir_ + "/c4.stl", c5_stl = dir_ + "/c5.stl";
  ASSERT_TRUE(save_mesh_file(generated.vertebra(VertebraLevel::kC4), c4_obj, MeshFormat::kObj, LengthUnit::kMillimetre, &error)) << error;
  ASSERT_TRUE(save_mesh_file(generated.vertebra(VertebraLevel::kC5), c5_obj, MeshFormat::kObj, LengthUnit::kMillimetre, &error)) << error;
  ASSERT_TRUE(save_mesh_file(generated.vertebra(VertebraLevel::kC4), c4_stl, MeshFormat::kStlBinary, LengthUnit::kMillimetre, &error)) << error;
  ASSERT_TRUE(save_mesh_file(generated.vertebra(VertebraLevel::kC5), c5_stl, MeshFormat::kStlBinary, LengthUnit::kMillimetre, &error)) << error;
  AnatomyConfig obj = coarse("none");
  obj.c4_mesh_path = c4_obj;
  obj.c5_mesh_path = c5_obj;
  AnatomyConfig stl = obj;
  stl.c4_mesh_path = c4_stl;
  stl.c5_mesh_path = c5_stl;
  EXPECT_EQ(check_anatomy_files(obj), "");
  const Anatomy a(obj), b(stl);
  EXPECT_TRUE(a.report().meshes_from_files);
  for (VertebraLevel level : {VertebraLevel::kC4, VertebraLevel::kC5}) {
    EXPECT_EQ(a.vertebra(level).content_hash(), b.vertebra(level).content_hash());
  }
  ASSERT_EQ(a.bone_grid().values().size(), b.bone_grid().values().size());
  EXPECT_TRUE(std::equal(a.bone_grid().values().begin(), a.bone_grid().values().end(), b.bone_grid().values().begin()));

  // A broken file: a clear error before anything is built, and from the constructor.
  TriangleMesh open = generated.vertebra(VertebraLevel::kC5);
  open.triangles.resize(open.triangles.size() / 2);
  ASSERT_TRUE(save_mesh_file(open, c5_stl, MeshFormat::kStlBinary, LengthUnit::kMillimetre, &error));
  const std::string problem = check_anatomy_files(stl);
  EXPECT_NE(problem.find(c5_stl + ": not a closed surface:"), std::string::npos) << problem;
  EXPECT_THROW(Anatomy broken(stl), std::runtime_error);
}

TEST(ParticleBlock, EllipticRingWithWindow) {
  ParticleBlockConfig b;
  b.min_m = Vec3(-7, -3, -7) * kMm;
  b.max_m = Vec3(7, 3, 7) * kMm;
  b.shape = BlockShape::kEllipticCylinder;
  b.axis = 1;
  b.semi_a_m = 6 * kMm;   // x
  b.semi_b_m = 5 * kMm;   // z
  b.hole_a_m = 4 * kMm;
  b.hole_b_m = 3 * kMm;
  b.has_cutout = true;
  b.cutout_min_m = Vec3(-2, -3, 0) * kMm;
  b.cutout_max_m = Vec3(2, 3, 7) * kMm;
  EXPECT_FALSE(b.contains(Vec3(0, 0, 0)));             // in the hole
  EXPECT_TRUE(b.contains(Vec3(5 * kMm, 0, 0)));        // in the ring
  EXPECT_FALSE(b.contains(Vec3(6.5 * kMm, 0, 0)));     // outside the ellipse
  EXPECT_TRUE(b.contains(Vec3(0, 2 * kMm, -4 * kMm))); // ring, behind
  EXPECT_FALSE(b.contains(Vec3(0, 0, 4 * kMm)));       // ring, but in the window
  EXPECT_FALSE(b.contains(Vec3(5 * kMm, 3.5 * kMm, 0)));  // above the box
  b.hole_a_m = b.hole_b_m = 0.0;
  b.has_cutout = false;
  EXPECT_TRUE(b.contains(Vec3(0, 0, 0)));              // a solid cylinder
}

TEST_F(AnatomyTest, WorldStepsWithBoneAndZoneSamples) {
  const WorldConfig w = test::coarse_segment_world(dir_);
  World world(w);
  ASSERT_NE(world.anatomy(), nullptr);
  EXPECT_EQ(world.summary().zones.size(), 7u);
  EXPECT_EQ(world.summary().zones[0].name, "vertebral_artery_left");
  EXPECT_GT(world.summary().initial_target, 100);
  // Push the cup down onto the C5 endplate's front edge: bone contact is measured.
  DeviceSample s;
  s.pose = test::coarse_segment_push(w);
  double peak_contact = 0.0;
  for (int i = 0; i < 300; ++i) {
    s.t_s = world.time_s();
    peak_contact = std::max(peak_contact, world.step(s).contact_force_N.norm());
  }
  const Frame& f = world.last_frame();
  EXPECT_FALSE(world.failed());
  EXPECT_EQ(f.zone_count, 7);
  // The endplate of C5 is touched or within its warning distance; the arteries are far.
  EXPECT_TRUE(f.zones[6].warning) << f.zones[6].distance_m;
  EXPECT_GT(f.zones[0].distance_m, 5e-3);
  EXPECT_GT(peak_contact, 0.01);  // Bullet's bone mesh stops the cup
  std::vector<Event> events;
  world.drain_events(events);
  bool warned = false;
  for (const Event& e : events) warned = warned || (e.kind == EventKind::kZoneWarning && e.zone == 6);
  EXPECT_TRUE(warned);
}


// The posterior longitudinal ligament: the cup driven backward through a block of gel at the
// back of the disc space pushes the back rows toward the canal. With the ligament they stop
// at its face (half a lattice spacing behind the bodies); without it they enter the canal.
// The blade itself passes the ligament: the rigid world does not see it.
struct LigamentPush {
  double min_z_m = 0.0;          // the rearmost particle centre over the push
  double peak_contact_N = 0.0;   // rigid contact on the instrument
  double cord_distance_m = 0.0;  // the cup from the cord zone at the deepest point
};

LigamentPush push_toward_the_canal(const std::string& dir, bool ligament) {
  WorldConfig w = test::coarse_segment_world(dir);
  w.anatomy.posterior_ligament = ligament;
  ParticleBlockConfig back;  // 4 x 5 x 4 rows, the rearmost at z = -8 mm (bodies' wall -8.05)
  back.min_m = Vec3(-2.0, -2.5, -8.5) * kMm;
  back.max_m = Vec3(2.0, 2.5, -4.5) * kMm;
  w.nucleus.blocks = {back};
  World world(w);
  const double start_z = w.instrument_start.position.z();
  double cup_z = 0.0;  // the cup shell's centre
  for (const Collider& c : world.instrument_colliders())
    if (c.kind == ColliderKind::kCupShell) cup_z = c.pose.position.z();
  const double cup_offset = start_z - cup_z;  // grip to cup centre along z
  LigamentPush out;
  out.min_z_m = 1.0;
  DeviceSample s;
  s.pose = w.instrument_start;
  // 1.2 s down to the cup centre at z = -9.8 mm (its back 1.5 mm further, through the
  // ligament's face), then 0.3 s held.
  const double end_z = -9.8 * kMm + cup_offset;
  for (int i = 0; i < 1500; ++i) {
    const double a = std::min(1.0, world.time_s() / 1.2);
    s.t_s = world.time_s();
    s.pose.position.z() = start_z + a * (end_z - start_z);
    const Frame& f = world.step(s);
    out.peak_contact_N = std::max(out.peak_contact_N, f.contact_force_N.norm());
    for (const Vec3& x : world.nucleus()->positions()) out.min_z_m = std::min(out.min_z_m, x.z());
    out.cord_distance_m = f.zones[4].distance_m;  // spinal_cord_pll
  }
  EXPECT_FALSE(world.failed());
  return out;
}

TEST_F(AnatomyTest, PosteriorLigamentHoldsTheDiscAndLetsTheBladePass) {
  World probe(test::coarse_segment_world(dir_));
  const SegmentLandmarks& l = probe.anatomy()->landmarks();
  ASSERT_EQ(probe.summary().zones[4].name, "spinal_cord_pll");
  const double face = l.body_back_z_m - 0.5 * kMm;  // half the 1 mm spacing behind the bodies
  const LigamentPush with = push_toward_the_canal(dir_, true);
  const LigamentPush without = push_toward_the_canal(dir_, false);
  std::printf("rearmost particle: %.3f mm with the ligament, %.3f mm without (face %.3f mm); "
              "peak rigid contact %.4f / %.4f N; cup from the cord zone %.2f mm\n",
              with.min_z_m / kMm, without.min_z_m / kMm, face / kMm, with.peak_contact_N,
              without.peak_contact_N, with.cord_distance_m / kMm);
  // Held: no particle centre comes within a quarter spacing of the face.
  EXPECT_GT(with.min_z_m, face + 0.25 * kMm);
  // Not held: pushed past where the ligament's face would be.
  EXPECT_LT(without.min_z_m, face);
  // The cup went through the ligament into the cord zone's warning band, as without it.
  EXPECT_LT(with.cord_distance_m, 1.0 * kMm);
  EXPECT_NEAR(with.peak_contact_N, without.peak_contact_N, 0.02);
}

}  // namespace
}  // namespace acdr
