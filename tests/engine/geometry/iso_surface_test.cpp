// Marching tetrahedra: closed, outward, and close to the implicit surface it samples.
#include "engine/geometry/iso_surface.hpp"

#include <gtest/gtest.h>

#include <numbers>

namespace acdr {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(IsoSurface, SphereIsClosedOutwardAndOnTheSurface) {
  const double r = 3e-3, h = 0.25e-3;
  const Vec3 c(0.1e-3, -0.2e-3, 0.05e-3);  // off the grid's symmetry
  const auto f = [&](const Vec3& p) { return (p - c).norm() - r; };
  const ScalarGrid g = sample_function(f, Vec3::Constant(-4e-3), Vec3::Constant(4e-3), h);
  const TriangleMesh m = extract_iso_surface(g);
  const MeshCheck check = check_closed_mesh(m);
  ASSERT_TRUE(check.ok) << check.error;
  EXPECT_NEAR(check.volume_m3 / (4.0 / 3.0 * kPi * r * r * r), 1.0, 0.01);
  // Linear interpolation of an exact distance: every vertex within a small fraction of h.
  for (const Vec3& v : m.vertices) EXPECT_NEAR((v - c).norm(), r, 0.05 * h);
}

TEST(IsoSurface, TorusKeepsItsHoleAndSeparateSolidsStaySeparate) {
  const double R = 4e-3, a = 1.2e-3;
  const auto torus = [&](const Vec3& p) {
    const double q = std::hypot(p.x(), p.y()) - R;
    return std::hypot(q, p.z()) - a;
  };
  const TriangleMesh t =
      extract_iso_surface(sample_function(torus, Vec3(-6e-3, -6e-3, -2e-3), Vec3(6e-3, 6e-3, 2e-3), 0.2e-3));
  const MeshCheck ct = check_closed_mesh(t);
  ASSERT_TRUE(ct.ok) << ct.error;
  // Euler characteristic V - E + F = 0 for a torus (E = 3F/2 on a closed triangle mesh).
  const long V = static_cast<long>(t.vertex_count()), F = static_cast<long>(t.triangle_count());
  EXPECT_EQ(V - 3 * F / 2 + F, 0);
  EXPECT_NEAR(ct.volume_m3 / (2 * kPi * kPi * R * a * a), 1.0, 0.02);

  const auto two = [](const Vec3& p) {
    return std::min((p - Vec3(-3e-3, 0, 0)).norm(), (p - Vec3(3e-3, 0, 0)).norm()) - 2e-3;
  };
  const TriangleMesh s =
      extract_iso_surface(sample_function(two, Vec3(-6e-3, -3e-3, -3e-3), Vec3(6e-3, 3e-3, 3e-3), 0.3e-3));
  const MeshCheck cs = check_closed_mesh(s);
  ASSERT_TRUE(cs.ok) << cs.error;
  EXPECT_EQ(static_cast<long>(s.vertex_count()) - 3 * static_cast<long>(s.triangle_count()) / 2 +
                static_cast<long>(s.triangle_count()),
            4);  // two spheres: chi = 2 + 2
}

TEST(IsoSurface, SamplesOnTheSurfaceDoNotDegenerate) {
  // A box whose faces lie exactly on grid planes: many samples are exactly 0.
  const auto box = [](const Vec3& p) {
    const Vec3 d = p.cwiseAbs() - Vec3(1e-3, 1e-3, 1e-3);
    return std::max({d.x(), d.y(), d.z()});
  };
  const TriangleMesh m =
      extract_iso_surface(sample_function(box, Vec3::Constant(-2e-3), Vec3::Constant(2e-3), 0.25e-3));
  const MeshCheck c = check_closed_mesh(m);
  EXPECT_TRUE(c.ok) << c.error;
  EXPECT_NEAR(c.volume_m3, 8e-9, 0.05 * 8e-9);
}

TEST(IsoSurface, CoarseToFineSamplingGivesTheSameSurface) {
  // A union of a box and a rod: a bound on the distance, not exact, still 1-Lipschitz.
  const auto f = [](const Vec3& p) {
    const Vec3 q = p.cwiseAbs() - Vec3(2e-3, 1e-3, 1.5e-3);
    const double box = q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
    const double rod = std::max(std::hypot(p.y(), p.z() - 1.5e-3) - 0.8e-3, std::abs(p.x()) - 4e-3);
    return std::min(box, rod);
  };
  const Vec3 lo(-6e-3, -3e-3, -3e-3), hi(6e-3, 3e-3, 4e-3);
  const ScalarGrid full = sample_function(f, lo, hi, 0.2e-3, false);
  const ScalarGrid fast = sample_function(f, lo, hi, 0.2e-3, true);
  const TriangleMesh a = extract_iso_surface(full), b = extract_iso_surface(fast);
  EXPECT_EQ(a.content_hash(), b.content_hash());
  EXPECT_GT(a.triangle_count(), 1000u);
}

TEST(IsoSurface, EmptyWhenNothingCrosses) {
  const auto outside = [](const Vec3&) { return 1.0; };
  EXPECT_EQ(extract_iso_surface(sample_function(outside, Vec3::Zero(), Vec3::Constant(1e-3), 0.5e-3))
                .triangle_count(),
            0u);
}

}  // namespace
}  // namespace acdr
