#include "ui/mesh_silhouette.hpp"

#include <gtest/gtest.h>

#include "engine/geometry/mesh_shapes.hpp"

namespace acdr {
namespace {

int covered_cells(const MeshSilhouette& s) {
  int n = 0;
  for (const MeshSilhouette::Run& r : s.runs) n += r.last - r.first + 1;
  return n;
}

TEST(MeshSilhouette, ABoxCastsItsRectangleOnEachPlane) {
  // 10 x 6 x 4 mm; cells of 0.5 mm: 20 x 12 cells from above, 20 x 8 from the side.
  const TriangleMesh box = make_box_mesh(Vec3(0, 0, 0), Vec3(10e-3, 6e-3, 4e-3));
  const MeshSilhouette top = project_silhouette({&box}, 0, 1, 0.5e-3);
  const MeshSilhouette side = project_silhouette({&box}, 0, 2, 0.5e-3);
  EXPECT_EQ(covered_cells(top), 20 * 12);
  EXPECT_EQ(covered_cells(side), 20 * 8);
  EXPECT_EQ(top.runs.size(), 12u);  // one run per row
  EXPECT_DOUBLE_EQ(top.origin_a, 0.0);
  for (const MeshSilhouette::Run& r : top.runs) {
    EXPECT_EQ(r.first, 0);
    EXPECT_EQ(r.last, 19);
  }
}

TEST(MeshSilhouette, TwoMeshesApartLeaveTheGapBetweenThemEmpty) {
  // Two vertebra-like blocks 2 mm apart along y: seen from the front the gap is a row band.
  const TriangleMesh upper = make_box_mesh(Vec3(0, 3e-3, 0), Vec3(4e-3, 5e-3, 4e-3));
  const TriangleMesh lower = make_box_mesh(Vec3(0, 0, 0), Vec3(4e-3, 1e-3, 4e-3));
  const MeshSilhouette front = project_silhouette({&upper, &lower}, 0, 1, 0.5e-3);
  EXPECT_EQ(covered_cells(front), 8 * 2 + 8 * 4);
  for (const MeshSilhouette::Run& r : front.runs) EXPECT_TRUE(r.row < 2 || r.row >= 6) << r.row;
}

TEST(MeshSilhouette, NothingToProjectGivesNoRuns) {
  EXPECT_TRUE(project_silhouette({}, 0, 1, 0.5e-3).empty());
  const TriangleMesh box = make_box_mesh(Vec3(0, 0, 0), Vec3(1e-3, 1e-3, 1e-3));
  EXPECT_TRUE(project_silhouette({&box}, 0, 1, 0.0).empty());
}

}  // namespace
}  // namespace acdr
