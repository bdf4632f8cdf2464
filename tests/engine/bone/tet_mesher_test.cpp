// Volume meshing: a closed surface meets the quality limits; a surface that cannot bound a
// solid (open, degenerate, self-intersecting) or bad parameters give a returned error.
#include "engine/bone/tet_mesher.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include "engine/geometry/mesh_shapes.hpp"

namespace acdr {
namespace {

TEST(TetMesher, SphereMeetsTheQualityLimitsAndKeepsItsVolume) {
  const double r = 5e-3;
  const TriangleMesh sphere = make_sphere_mesh(Vec3(1e-3, 0, 0), r, 3);
  TetMeshingParams p;
  p.size_m = 1.5e-3;
  const TetMeshingResult result = mesh_closed_surface(sphere, p);
  ASSERT_TRUE(result.mesh) << result.error;
  EXPECT_EQ(result.error, "");
  const TetMesh& m = *result.mesh;
  EXPECT_GT(m.tets.size(), 200u);
  EXPECT_EQ(result.quality.inverted, 0u);
  EXPECT_GE(result.quality.min_dihedral_deg, p.limits.min_dihedral_deg);
  EXPECT_LE(result.quality.max_aspect_ratio, p.limits.max_aspect_ratio);
  // Within 5 % of the input polyhedron's volume: the re-sampled surface is itself a polyhedron
  // inscribed in it (1.5 mm facets on a 5 mm radius cut ~3 %).
  EXPECT_NEAR(m.volume() / sphere.signed_volume(), 1.0, 0.05);
  EXPECT_LT(m.volume(), sphere.signed_volume());
  for (std::size_t t = 0; t < m.tets.size(); ++t) ASSERT_GT(m.tet_volume(t), 0.0);
  // Smaller elements, more of them.
  p.size_m = 1.0e-3;
  const TetMeshingResult finer = mesh_closed_surface(sphere, p);
  ASSERT_TRUE(finer.mesh) << finer.error;
  EXPECT_GT(finer.mesh->tets.size(), 2 * m.tets.size());
}

TEST(TetMesher, SameSurfaceSameMesh) {
  const TriangleMesh box = make_box_mesh(Vec3::Zero(), Vec3(6e-3, 4e-3, 3e-3));
  TetMeshingParams p;
  p.size_m = 1.5e-3;
  const auto a = mesh_closed_surface(box, p), b = mesh_closed_surface(box, p);
  ASSERT_TRUE(a.mesh && b.mesh) << a.error;
  EXPECT_EQ(a.mesh->serialize(), b.mesh->serialize());
}

TEST(TetMesher, OpenSurfaceIsRefusedWithWhereTheHoleIs) {
  TriangleMesh box = make_box_mesh(Vec3::Zero(), Vec3(5e-3, 5e-3, 5e-3));
  box.triangles.pop_back();
  const TetMeshingResult r = mesh_closed_surface(box, TetMeshingParams{});
  EXPECT_FALSE(r.mesh);
  EXPECT_NE(r.error.find("not a closed surface"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("open edges"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("mm)"), std::string::npos) << r.error;
}

TEST(TetMesher, DegenerateTriangleIsRefused) {
  TriangleMesh box = make_box_mesh(Vec3::Zero(), Vec3(5e-3, 5e-3, 5e-3));
  box.triangles[0][2] = box.triangles[0][1];
  const TetMeshingResult r = mesh_closed_surface(box, TetMeshingParams{});
  EXPECT_FALSE(r.mesh);
  EXPECT_NE(r.error.find("degenerate"), std::string::npos) << r.error;
}

TEST(TetMesher, SelfIntersectingSurfaceIsRefused) {
  // Two closed boxes that overlap: every edge is shared properly, yet the surface crosses itself.
  TriangleMesh two = make_box_mesh(Vec3::Zero(), Vec3(5e-3, 5e-3, 5e-3));
  two.append(make_box_mesh(Vec3(2e-3, 2e-3, 2e-3), Vec3(7e-3, 7e-3, 7e-3)));
  ASSERT_TRUE(check_closed_mesh(two).ok);
  const TetMeshingResult r = mesh_closed_surface(two, TetMeshingParams{});
  EXPECT_FALSE(r.mesh);
  EXPECT_NE(r.error.find("intersects itself"), std::string::npos) << r.error;
}

TEST(TetMesher, InsideOutSurfaceIsRefused) {
  TriangleMesh box = make_box_mesh(Vec3::Zero(), Vec3(5e-3, 5e-3, 5e-3));
  for (auto& t : box.triangles) std::swap(t[1], t[2]);
  const TetMeshingResult r = mesh_closed_surface(box, TetMeshingParams{});
  EXPECT_FALSE(r.mesh);
  EXPECT_FALSE(r.error.empty());
}

TEST(TetMesher, BadParametersAreNamed) {
  TetMeshingParams p;
  p.size_m = -1e-3;
  p.radius_edge_ratio = 1.0;
  const TetMeshingResult r =
      mesh_closed_surface(make_box_mesh(Vec3::Zero(), Vec3::Ones() * 1e-3), p);
  EXPECT_FALSE(r.mesh);
  EXPECT_NE(r.error.find("size_m: got -1 mm"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("radius_edge_ratio"), std::string::npos) << r.error;
}

}  // namespace
}  // namespace acdr
