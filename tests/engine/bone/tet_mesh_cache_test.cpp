// The volume-mesh cache: a second request loads the same mesh; other parameters miss; a
// damaged file is meshed again and said so.
#include "engine/bone/tet_mesh_cache.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "engine/core/disk_cache.hpp"
#include "engine/geometry/mesh_shapes.hpp"

namespace acdr {
namespace {

class TetMeshCache : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = (std::filesystem::temp_directory_path() /
            ("acdr_tet_cache_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
             "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name()))
               .string();
    std::filesystem::remove_all(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string dir_;
};

TEST_F(TetMeshCache, SecondRequestLoadsTheSameMesh) {
  const TriangleMesh sphere = make_sphere_mesh(Vec3::Zero(), 4e-3, 3);
  TetMeshingParams p;
  p.size_m = 1.5e-3;
  TetMeshLoadInfo first, second;
  std::string error;
  const auto a = load_or_mesh_surface(sphere, p, dir_, &first, &error);
  ASSERT_TRUE(a) << error;
  EXPECT_FALSE(first.from_cache);
  EXPECT_TRUE(
      std::filesystem::exists(cache_file_path(dir_, tet_mesh_cache_key(sphere, p), ".tet")));
  const auto b = load_or_mesh_surface(sphere, p, dir_, &second, &error);
  ASSERT_TRUE(b) << error;
  EXPECT_TRUE(second.from_cache);
  EXPECT_EQ(a->serialize(), b->serialize());
  EXPECT_EQ(second.quality.tets, first.quality.tets);
  EXPECT_EQ(second.note, "");

  // Other parameters, another key: meshed, not loaded.
  TetMeshingParams q = p;
  q.size_m = 2.0e-3;
  EXPECT_NE(tet_mesh_cache_key(sphere, q), tet_mesh_cache_key(sphere, p));
  TetMeshLoadInfo third;
  ASSERT_TRUE(load_or_mesh_surface(sphere, q, dir_, &third, &error));
  EXPECT_FALSE(third.from_cache);
  // Another surface, another key.
  EXPECT_NE(tet_mesh_cache_key(make_sphere_mesh(Vec3::Zero(), 4.1e-3, 3), p),
            tet_mesh_cache_key(sphere, p));
}

TEST_F(TetMeshCache, DamagedFileIsMeshedAgainWithANote) {
  const TriangleMesh box = make_box_mesh(Vec3::Zero(), Vec3(4e-3, 4e-3, 4e-3));
  TetMeshingParams p;
  p.size_m = 2e-3;
  std::string error;
  ASSERT_TRUE(load_or_mesh_surface(box, p, dir_, nullptr, &error)) << error;
  const std::string path = cache_file_path(dir_, tet_mesh_cache_key(box, p), ".tet");
  std::ofstream(path, std::ios::binary | std::ios::trunc) << "garbage";
  TetMeshLoadInfo info;
  const auto m = load_or_mesh_surface(box, p, dir_, &info, &error);
  ASSERT_TRUE(m) << error;
  EXPECT_FALSE(info.from_cache);
  EXPECT_NE(info.note.find("meshed again"), std::string::npos) << info.note;
  // The rewritten file loads next time.
  TetMeshLoadInfo again;
  ASSERT_TRUE(load_or_mesh_surface(box, p, dir_, &again, &error));
  EXPECT_TRUE(again.from_cache);
}

TEST_F(TetMeshCache, CachedMeshBelowTheQualityLimitsIsMeshedAgain) {
  const TriangleMesh box = make_box_mesh(Vec3::Zero(), Vec3(4e-3, 4e-3, 4e-3));
  TetMeshingParams p;
  p.size_m = 2e-3;
  // A file under the right key holding a sliver.
  TetMesh sliver;
  sliver.nodes = {Vec3(0, 0, 0), Vec3(1e-3, 0, 0), Vec3(0, 1e-3, 0), Vec3(1e-3, 1e-3, 1e-6)};
  sliver.tets = {{0, 1, 2, 3}};
  sliver.region = {0};
  std::string error;
  ASSERT_TRUE(write_cache_file(cache_file_path(dir_, tet_mesh_cache_key(box, p), ".tet"),
                               sliver.serialize(), &error));
  TetMeshLoadInfo info;
  const auto m = load_or_mesh_surface(box, p, dir_, &info, &error);
  ASSERT_TRUE(m) << error;
  EXPECT_FALSE(info.from_cache);
  EXPECT_NE(info.note.find("minimum dihedral angle"), std::string::npos) << info.note;
  EXPECT_GT(m->tets.size(), 1u);
}

TEST_F(TetMeshCache, UnmeshableSurfaceIsAnErrorAndNotCached) {
  TriangleMesh box = make_box_mesh(Vec3::Zero(), Vec3(4e-3, 4e-3, 4e-3));
  box.triangles.pop_back();
  std::string error;
  EXPECT_FALSE(load_or_mesh_surface(box, TetMeshingParams{}, dir_, nullptr, &error));
  EXPECT_NE(error.find("not a closed surface"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir_) && !std::filesystem::is_empty(dir_));
}

}  // namespace
}  // namespace acdr
