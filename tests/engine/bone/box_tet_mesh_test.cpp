// The structured box mesh: counts, orientation, conformity between cubes.
#include "engine/bone/box_tet_mesh.hpp"

#include <gtest/gtest.h>

namespace acdr {
namespace {

TEST(BoxTetMesh, CountsAndPositiveVolumes) {
  const TetMesh m = make_box_tet_mesh(Vec3(-1, 0, 0), Vec3(1, 1, 3), {2, 1, 3});
  EXPECT_EQ(m.nodes.size(), 3u * 2u * 4u);
  EXPECT_EQ(m.tets.size(), 6u * 6u);
  for (std::size_t t = 0; t < m.tets.size(); ++t) EXPECT_GT(m.tet_volume(t), 0.0);
  EXPECT_NEAR(m.volume(), 6.0, 1e-12);
}

TEST(BoxTetMesh, NeighbouringCubesShareTheirFaces) {
  // Conforming: interior faces pair up, so only the box's own surface is boundary.
  const TetMesh m = make_box_tet_mesh(Vec3::Zero(), Vec3::Ones(), {3, 3, 3});
  EXPECT_EQ(boundary_faces(m).size(), 6u * 9u * 2u);
}

}  // namespace
}  // namespace acdr
