// Tests of ui/mesh_normals: sharp edges split, smooth surfaces stay smooth, bad triangles drop.
#include "ui/mesh_normals.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace acdr {
namespace {

// A unit cube with 8 shared corners and 12 outward (counter-clockwise) triangles.
void shared_cube(std::vector<Eigen::Vector3f>* v, std::vector<std::uint32_t>* i) {
  for (int c = 0; c < 8; ++c) v->emplace_back(c & 1, (c >> 1) & 1, (c >> 2) & 1);
  *i = {0, 2, 3, 0, 3, 1,  4, 5, 7, 4, 7, 6,  0, 1, 5, 0, 5, 4,
        2, 6, 7, 2, 7, 3,  0, 4, 6, 0, 6, 2,  1, 3, 7, 1, 7, 5};
}

TEST(MeshNormals, SplitsACubeIntoFlatFaces) {
  std::vector<Eigen::Vector3f> v;
  std::vector<std::uint32_t> i;
  shared_cube(&v, &i);
  const NormalMesh m = compute_crease_normals(v, i);
  // Each corner touches three faces at right angles: three copies, 24 vertices in all.
  EXPECT_EQ(m.positions.size(), 24u);
  ASSERT_EQ(m.indices.size(), 36u);
  for (std::size_t t = 0; t < m.indices.size(); t += 3) {
    const Eigen::Vector3f& a = m.positions[m.indices[t]];
    const Eigen::Vector3f face =
        (m.positions[m.indices[t + 1]] - a).cross(m.positions[m.indices[t + 2]] - a).normalized();
    for (int k = 0; k < 3; ++k) {
      // Flat and outward: every corner's normal is its face's normal.
      EXPECT_NEAR(m.normals[m.indices[t + k]].dot(face), 1.0f, 1e-5f);
    }
  }
}

TEST(MeshNormals, KeepsASphereSmooth) {
  // A latitude-longitude sphere with shared vertices (poles shared too).
  const int rings = 16, segments = 32;
  std::vector<Eigen::Vector3f> v;
  std::vector<std::uint32_t> idx;
  v.emplace_back(0, 0, 1);
  for (int r = 1; r < rings; ++r) {
    const float th = 3.14159265f * r / rings;
    for (int s = 0; s < segments; ++s) {
      const float ph = 2 * 3.14159265f * s / segments;
      v.emplace_back(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
    }
  }
  v.emplace_back(0, 0, -1);
  const std::uint32_t south = static_cast<std::uint32_t>(v.size() - 1);
  auto ring = [&](int r, int s) { return 1 + (r - 1) * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) {
    idx.insert(idx.end(), {0u, static_cast<std::uint32_t>(ring(1, s)),
                           static_cast<std::uint32_t>(ring(1, s + 1))});
    for (int r = 1; r < rings - 1; ++r) {
      const std::uint32_t a = ring(r, s), b = ring(r, s + 1), c = ring(r + 1, s + 1),
                          d = ring(r + 1, s);
      idx.insert(idx.end(), {a, d, c, a, c, b});
    }
    idx.insert(idx.end(), {static_cast<std::uint32_t>(ring(rings - 1, s)), south,
                           static_cast<std::uint32_t>(ring(rings - 1, s + 1))});
  }
  const NormalMesh m = compute_crease_normals(v, idx);
  EXPECT_EQ(m.positions.size(), v.size());  // nothing split
  for (std::size_t k = 0; k < m.positions.size(); ++k) {
    EXPECT_GT(m.normals[k].dot(m.positions[k].normalized()), 0.995f) << k;
  }
}

TEST(MeshNormals, DropsTrianglesWithBadIndicesOrNoArea) {
  const std::vector<Eigen::Vector3f> v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}};
  const std::vector<std::uint32_t> i = {0, 1, 2, 0, 1, 9, 0, 1, 3};  // good, out of range, flat
  int dropped = 0;
  const NormalMesh m = compute_crease_normals(v, i, 35.0f, &dropped);
  EXPECT_EQ(dropped, 2);
  EXPECT_EQ(m.indices.size(), 3u);
  EXPECT_NEAR(m.normals[0].z(), 1.0f, 1e-6f);
}

}  // namespace
}  // namespace acdr
