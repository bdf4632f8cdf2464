// Tetrahedral mesh basics: volumes, boundary faces, shape figures, the cache byte form.
#include "engine/bone/tet_mesh.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "engine/bone/box_tet_mesh.hpp"

namespace acdr {
namespace {

TEST(TetMesh, BoxVolumeAndBoundaryFacesCloseTheSolid) {
  const TetMesh m = make_box_tet_mesh(Vec3(0, 0, 0), Vec3(2e-3, 3e-3, 4e-3), {2, 3, 4});
  EXPECT_NEAR(m.volume(), 24e-9, 1e-20);
  const auto faces = boundary_faces(m);
  // Two triangles per boundary square: 2 (2*3 + 2*4 + 3*4) squares.
  EXPECT_EQ(faces.size(), 2u * 2u * (6 + 8 + 12));
  // Outward faces: the divergence theorem gives the volume back, and the normals cancel.
  double volume = 0.0;
  Vec3 normal_sum = Vec3::Zero();
  for (const auto& f : faces) {
    const Vec3 &a = m.nodes[f.nodes[0]], &b = m.nodes[f.nodes[1]], &c = m.nodes[f.nodes[2]];
    volume += a.dot(b.cross(c)) / 6.0;
    normal_sum += (b - a).cross(c - a);
  }
  EXPECT_NEAR(volume, 24e-9, 1e-20);
  EXPECT_LT(normal_sum.norm(), 1e-18);
}

TEST(TetMesh, RegularTetHasTheTextbookShape) {
  const Vec3 a(1, 1, 1), b(1, -1, -1), c(-1, 1, -1), d(-1, -1, 1);
  // Inverted (negative volume) as listed: reported as a flat tet.
  EXPECT_EQ(tet_shape(a, b, c, d).min_dihedral_deg, 0.0);
  const TetShape s = tet_shape(a, b, d, c);
  EXPECT_NEAR(s.min_dihedral_deg, std::acos(1.0 / 3.0) * 180.0 / M_PI, 1e-9);
  EXPECT_NEAR(s.max_dihedral_deg, s.min_dihedral_deg, 1e-9);
  EXPECT_NEAR(s.aspect_ratio, 1.0, 1e-12);
}

TEST(TetMesh, SliverIsFoundAndRefused) {
  // Four nearly coplanar points: a sliver with dihedral angles near 0 and 180 degrees.
  TetMesh m;
  m.nodes = {Vec3(0, 0, 0), Vec3(1e-3, 0, 0), Vec3(0, 1e-3, 0), Vec3(1e-3, 1e-3, 1e-6)};
  m.tets = {{0, 1, 2, 3}};
  if (m.tet_volume(0) < 0) std::swap(m.tets[0][2], m.tets[0][3]);
  const TetQuality q = tet_quality(m);
  EXPECT_LT(q.min_dihedral_deg, 1.0);
  EXPECT_GT(q.max_aspect_ratio, 100.0);
  const std::string why = check_tet_quality(q, TetQualityLimits{});
  EXPECT_NE(why.find("minimum dihedral angle"), std::string::npos) << why;
  EXPECT_NE(why.find("aspect ratio"), std::string::npos) << why;
  // The Kuhn split of a cube passes.
  const TetQuality box = tet_quality(make_box_tet_mesh(Vec3::Zero(), Vec3::Ones(), {2, 2, 2}));
  EXPECT_EQ(check_tet_quality(box, TetQualityLimits{}), "");
  EXPECT_EQ(box.inverted, 0u);
}

TEST(TetMesh, InvertedTetIsCounted) {
  TetMesh m = make_box_tet_mesh(Vec3::Zero(), Vec3::Ones(), {1, 1, 1});
  std::swap(m.tets[0][0], m.tets[0][1]);
  const TetQuality q = tet_quality(m);
  EXPECT_EQ(q.inverted, 1u);
  EXPECT_NE(check_tet_quality(q, TetQualityLimits{}).find("1 inverted"), std::string::npos);
}

TEST(TetMesh, SerializeRoundTripAndTruncation) {
  TetMesh m = make_box_tet_mesh(Vec3::Zero(), Vec3(1e-3, 1e-3, 1e-3), {2, 1, 1});
  m.region[3] = 2;
  const std::string bytes = m.serialize();
  std::string error;
  const auto back = TetMesh::deserialize(bytes, &error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->nodes, m.nodes);
  EXPECT_EQ(back->tets, m.tets);
  EXPECT_EQ(back->region, m.region);
  EXPECT_FALSE(TetMesh::deserialize(bytes.substr(0, bytes.size() - 1), &error));
  EXPECT_NE(error.find("truncated"), std::string::npos);
  EXPECT_FALSE(TetMesh::deserialize("not a mesh at all, no", &error));
}

}  // namespace
}  // namespace acdr
