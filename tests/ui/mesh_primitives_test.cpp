// Tests of ui/mesh_primitives: every shape is closed, outward-facing and of the right size,
// checked through its enclosed volume (divergence theorem) against the closed form.
#include "ui/mesh_primitives.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace acdr {
namespace {

constexpr double kPi = 3.14159265358979;

// Signed volume enclosed by the mesh (after its pose): positive when triangles turn
// counter-clockwise seen from outside.
double enclosed_volume(const RenderMesh& m) {
  double volume = 0.0;
  for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
    const Eigen::Vector3d a = (m.pose * m.vertices[m.indices[t]]).cast<double>();
    const Eigen::Vector3d b = (m.pose * m.vertices[m.indices[t + 1]]).cast<double>();
    const Eigen::Vector3d c = (m.pose * m.vertices[m.indices[t + 2]]).cast<double>();
    volume += a.dot(b.cross(c)) / 6.0;
  }
  return volume;
}

// Every stored normal is unit length and agrees with the winding of each triangle using it.
void expect_consistent_normals(const RenderMesh& m) {
  ASSERT_EQ(m.normals.size(), m.vertices.size());
  ASSERT_EQ(m.indices.size() % 3, 0u);
  for (const Eigen::Vector3f& n : m.normals) EXPECT_NEAR(n.norm(), 1.0f, 1e-5f);
  for (std::size_t t = 0; t < m.indices.size(); t += 3) {
    const Eigen::Vector3f& a = m.vertices[m.indices[t]];
    const Eigen::Vector3f face =
        (m.vertices[m.indices[t + 1]] - a).cross(m.vertices[m.indices[t + 2]] - a);
    for (int k = 0; k < 3; ++k) EXPECT_GT(face.dot(m.normals[m.indices[t + k]]), 0.0f);
  }
}

TEST(MeshPrimitives, BoxEnclosesItsVolume) {
  const RenderMesh m = make_box({-0.01f, 0.0f, 0.002f}, {0.03f, 0.02f, 0.012f});
  expect_consistent_normals(m);
  EXPECT_EQ(m.vertices.size(), 24u);
  EXPECT_NEAR(enclosed_volume(m), 0.04 * 0.02 * 0.01, 1e-10);
}

TEST(MeshPrimitives, BoxAcceptsSwappedCorners) {
  const RenderMesh m = make_box({1, 1, 1}, {0, 0, 0});
  EXPECT_NEAR(enclosed_volume(m), 1.0, 1e-6);
}

TEST(MeshPrimitives, OrientedBoxKeepsItsPose) {
  const Eigen::Affine3f pose = Eigen::Translation3f(1, 2, 3) *
                               Eigen::AngleAxisf(0.7f, Eigen::Vector3f(1, 1, 0).normalized());
  const RenderMesh m = make_oriented_box({0.5f, 1.0f, 2.0f}, pose);
  expect_consistent_normals(m);
  EXPECT_TRUE(m.pose.isApprox(pose));
  EXPECT_NEAR(enclosed_volume(m), 1.0 * 2.0 * 4.0, 1e-4);
}

TEST(MeshPrimitives, CylinderBetweenTwoPoints) {
  const Eigen::Vector3f a(0.0f, 0.0f, 0.0f), b(0.03f, 0.04f, 0.0f);  // length 0.05
  const float r = 0.002f;
  const int segments = 64;
  const RenderMesh m = make_cylinder(a, b, r, default_mesh_rgba(), segments);
  expect_consistent_normals(m);
  // The inscribed polygon's area: (n/2) r^2 sin(2 pi / n).
  const double area = 0.5 * segments * r * r * std::sin(2 * kPi / segments);
  EXPECT_NEAR(enclosed_volume(m), area * 0.05, 1e-12);
  // The end caps sit at the two points.
  float lo = 1e9f, hi = -1e9f;
  const Eigen::Vector3f axis = (b - a).normalized();
  for (const Eigen::Vector3f& v : m.vertices) {
    lo = std::min(lo, (v - a).dot(axis));
    hi = std::max(hi, (v - a).dot(axis));
  }
  EXPECT_NEAR(lo, 0.0f, 1e-6f);
  EXPECT_NEAR(hi, 0.05f, 1e-6f);
}

TEST(MeshPrimitives, CapsuleIsACylinderWithTwoHemispheres) {
  const float r = 0.001f, length = 0.01f;
  const RenderMesh m = make_capsule({0, 0, 0}, {0, 0, length}, r, default_mesh_rgba(), 96);
  expect_consistent_normals(m);
  const double exact = kPi * r * r * length + 4.0 / 3.0 * kPi * r * r * r;
  EXPECT_NEAR(enclosed_volume(m) / exact, 1.0, 0.01);
}

TEST(MeshPrimitives, SphereVolumeConverges) {
  const float r = 0.005f;
  const RenderMesh m = make_sphere({0.1f, -0.2f, 0.3f}, r, default_mesh_rgba(), 96);
  expect_consistent_normals(m);
  EXPECT_NEAR(enclosed_volume(m) / (4.0 / 3.0 * kPi * r * r * r), 1.0, 0.005);
  for (std::size_t k = 0; k < m.vertices.size(); ++k) {
    EXPECT_NEAR((m.vertices[k] - Eigen::Vector3f(0.1f, -0.2f, 0.3f)).norm(), r, 1e-6f);
  }
}

TEST(MeshPrimitives, CupShellHoldsTheVolumeBetweenTwoHemispheres) {
  const float inner = 0.002f, wall = 0.0004f;
  const Eigen::Vector3f center(0.0f, 0.01f, 0.0f);
  const Eigen::Vector3f opening(1.0f, 0.0f, 0.0f);
  const RenderMesh m = make_cup_shell(center, opening, inner, wall, default_mesh_rgba(), 96);
  expect_consistent_normals(m);
  const double outer = inner + wall;
  const double exact = 2.0 / 3.0 * kPi * (outer * outer * outer - inner * inner * inner);
  EXPECT_NEAR(enclosed_volume(m) / exact, 1.0, 0.01);
  // The bowl bulges away from the opening: nothing lies beyond the rim plane.
  for (const Eigen::Vector3f& v : m.vertices) EXPECT_LE((v - center).dot(opening), 1e-7f);
}

TEST(MeshPrimitives, AppendKeepsBothPartsAndTheirNormals) {
  RenderMesh m = make_box({0, 0, 0}, {1, 1, 1});
  append_mesh(m, make_box({2, 0, 0}, {3, 1, 2}));
  expect_consistent_normals(m);
  EXPECT_NEAR(enclosed_volume(m), 1.0 + 2.0, 1e-5);
}

}  // namespace
}  // namespace acdr
