// The closed-solid check: each kind of defect is found, counted and located.
#include "engine/geometry/triangle_mesh.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include "engine/geometry/mesh_shapes.hpp"

namespace acdr {
namespace {

TEST(TriangleMesh, BoxIsClosedWithItsVolumeAndArea) {
  const TriangleMesh box = make_box_mesh(Vec3(0, 0, 0), Vec3(2e-3, 3e-3, 4e-3));
  const MeshCheck c = check_closed_mesh(box);
  EXPECT_TRUE(c.ok) << c.error;
  EXPECT_NEAR(box.signed_volume(), 24e-9, 1e-20);
  EXPECT_NEAR(box.area(), 2 * (6e-6 + 8e-6 + 12e-6), 1e-18);
}

TEST(TriangleMesh, SphereVolumeApproachesTheBall) {
  const double r = 5e-3;
  const TriangleMesh s = make_sphere_mesh(Vec3(1e-3, 0, 0), r, 4);
  EXPECT_EQ(s.triangle_count(), 20u * 256u);
  const MeshCheck c = check_closed_mesh(s);
  ASSERT_TRUE(c.ok) << c.error;
  const double ball = 4.0 / 3.0 * std::numbers::pi * r * r * r;
  EXPECT_NEAR(c.volume_m3 / ball, 1.0, 0.01);  // inscribed polyhedron, slightly smaller
  EXPECT_LT(c.volume_m3, ball);
}

TEST(TriangleMesh, HoleIsReportedWithCountAndPlace) {
  TriangleMesh box = make_box_mesh(Vec3(0, 0, 0), Vec3(1e-3, 1e-3, 1e-3));
  box.triangles.pop_back();  // remove half of the x = hi face: 3 open edges
  const MeshCheck c = check_closed_mesh(box);
  EXPECT_FALSE(c.ok);
  EXPECT_EQ(c.open_edges, 3u);
  EXPECT_NE(c.error.find("3 open edges"), std::string::npos) << c.error;
  EXPECT_NE(c.error.find("mm)"), std::string::npos) << c.error;
}

TEST(TriangleMesh, FlippedTriangleIsFound) {
  TriangleMesh box = make_box_mesh(Vec3(0, 0, 0), Vec3(1e-3, 1e-3, 1e-3));
  std::swap(box.triangles[4][1], box.triangles[4][2]);
  const MeshCheck c = check_closed_mesh(box);
  EXPECT_FALSE(c.ok);
  EXPECT_EQ(c.flipped_edges, 3u);
  EXPECT_NE(c.error.find("disagree in orientation"), std::string::npos) << c.error;
}

TEST(TriangleMesh, InwardMeshIsRefused) {
  TriangleMesh box = make_box_mesh(Vec3(0, 0, 0), Vec3(1e-3, 1e-3, 1e-3));
  for (auto& t : box.triangles) std::swap(t[1], t[2]);
  const MeshCheck c = check_closed_mesh(box);
  EXPECT_FALSE(c.ok);
  EXPECT_LT(c.volume_m3, 0.0);
  EXPECT_NE(c.error.find("face inward"), std::string::npos) << c.error;
}

TEST(TriangleMesh, DegenerateAndOutOfRangeTrianglesAreFound) {
  TriangleMesh box = make_box_mesh(Vec3(0, 0, 0), Vec3(1e-3, 1e-3, 1e-3));
  box.triangles.push_back({0, 0, 1});
  box.triangles.push_back({0, 1, 99});
  const MeshCheck c = check_closed_mesh(box);
  EXPECT_FALSE(c.ok);
  EXPECT_EQ(c.degenerate_triangles, 1u);
  EXPECT_EQ(c.bad_indices, 1u);
  EXPECT_NE(c.error.find("vertex 99 of 8"), std::string::npos) << c.error;
}

TEST(TriangleMesh, NonManifoldEdgeIsFound) {
  // Two boxes sharing one edge's vertices: the edge is used by four triangles.
  TriangleMesh a = make_box_mesh(Vec3(0, 0, 0), Vec3(1e-3, 1e-3, 1e-3));
  TriangleMesh b = make_box_mesh(Vec3(1e-3, 1e-3, 0), Vec3(2e-3, 2e-3, 1e-3));
  a.append(b);
  a.weld_exact();
  const MeshCheck c = check_closed_mesh(a);
  EXPECT_FALSE(c.ok);
  EXPECT_EQ(c.non_manifold_edges, 1u);
}

TEST(TriangleMesh, WeldMergesIdenticalPointsInOrderOfUse) {
  TriangleMesh soup;
  const TriangleMesh box = make_box_mesh(Vec3(0, 0, 0), Vec3(1e-3, 1e-3, 1e-3));
  for (const auto& t : box.triangles) {
    const auto base = static_cast<std::uint32_t>(soup.vertices.size());
    for (int k = 0; k < 3; ++k) soup.vertices.push_back(box.vertices[t[k]]);
    soup.triangles.push_back({base, base + 1, base + 2});
  }
  EXPECT_EQ(soup.weld_exact(), 36u - 8u);
  EXPECT_TRUE(check_closed_mesh(soup).ok);
  // Renumbered by first use: the first triangle uses 0, 1, 2.
  EXPECT_EQ(soup.triangles[0], (std::array<std::uint32_t, 3>{0, 1, 2}));
  EXPECT_NE(soup.content_hash(), box.content_hash());  // same shape, other numbering
}

TEST(TriangleMesh, SerializeRoundTripsAndRefusesDamage) {
  const TriangleMesh s = make_sphere_mesh(Vec3(1e-3, 2e-3, 3e-3), 2e-3, 2);
  std::string bytes = s.serialize();
  std::string error;
  const auto back = TriangleMesh::deserialize(bytes, &error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->content_hash(), s.content_hash());
  bytes.pop_back();
  EXPECT_FALSE(TriangleMesh::deserialize(bytes, &error));
  EXPECT_NE(error.find("truncated"), std::string::npos) << error;
}

}  // namespace
}  // namespace acdr
