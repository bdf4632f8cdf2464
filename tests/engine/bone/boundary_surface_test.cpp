// Boundary faces in buckets: closest face and nearby faces agree with brute force.
#include "engine/bone/boundary_surface.hpp"

#include <gtest/gtest.h>

#include "engine/bone/box_tet_mesh.hpp"
#include "engine/geometry/signed_distance_grid.hpp"

namespace acdr {
namespace {

TEST(BoundarySurface, ClosestFaceMatchesBruteForce) {
  const TetMesh m = make_box_tet_mesh(Vec3::Zero(), Vec3(4e-3, 2e-3, 3e-3), {4, 2, 3});
  const BoundarySurface s(m);
  int checked = 0;
  for (double x : {-0.5e-3, 0.3e-3, 2.1e-3, 4.4e-3})
    for (double y : {0.1e-3, 1.0e-3, 2.5e-3})
      for (double z : {-0.2e-3, 1.4e-3, 2.9e-3}) {
        const Vec3 p(x, y, z);
        double brute = 1e9;
        for (const auto& f : s.faces()) {
          const Vec3 q = closest_point_on_triangle(p, m.nodes[f.nodes[0]], m.nodes[f.nodes[1]],
                                                   m.nodes[f.nodes[2]]);
          brute = std::min(brute, (q - p).norm());
        }
        double d = 0.0;
        Vec3 q;
        const int f = s.closest_face(p, 10e-3, &q, &d);
        ASSERT_GE(f, 0);
        EXPECT_NEAR(d, brute, 1e-15);
        EXPECT_NEAR((q - p).norm(), d, 1e-15);
        ++checked;
      }
  EXPECT_EQ(checked, 36);
  // Nothing within reach far away.
  EXPECT_EQ(s.closest_face(Vec3(20e-3, 0, 0), 1e-3, nullptr, nullptr), -1);
}

TEST(BoundarySurface, SurfaceNodesAndNormals) {
  const TetMesh m = make_box_tet_mesh(Vec3::Zero(), Vec3::Ones(), {2, 2, 2});
  const BoundarySurface s(m);
  int on = 0;
  for (auto v : s.on_surface()) on += v;
  EXPECT_EQ(on, 27 - 1);  // all but the centre node
  for (std::size_t f = 0; f < s.faces().size(); ++f) {
    const auto& n = s.faces()[f].nodes;
    const Vec3 c = (m.nodes[n[0]] + m.nodes[n[1]] + m.nodes[n[2]]) / 3.0 - Vec3::Constant(0.5);
    EXPECT_GT(c.dot(s.face_normal(f)), 0.0);  // outward
  }
  std::vector<std::uint32_t> near;
  s.faces_near(Vec3(0.5, 0.5, 1.0), 0.1, near);
  for (std::uint32_t f : near) EXPECT_GT(s.face_normal(f).z(), 0.99);  // only the top face's
  EXPECT_EQ(near.size(), 8u);
}

}  // namespace
}  // namespace acdr
