// Mesh signed distance grids: distances against brute force, robust signs, normals, clipping,
// the disk cache, and lookups that never allocate.
#include "engine/geometry/signed_distance_grid.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <random>

#include "engine/core/disk_cache.hpp"
#include "engine/geometry/mesh_shapes.hpp"
#include "engine/geometry/iso_surface.hpp"
#include "tests/support/counting_allocator.hpp"

namespace acdr {
namespace {

constexpr double kMm = 1e-3;

/// Exact signed distance to a closed mesh by brute force (sign from the closest feature's
/// angle-weighted... here simply from a known inside test).
double brute_distance(const TriangleMesh& m, const Vec3& p) {
  double best = 1e9;
  for (const auto& t : m.triangles) {
    best = std::min(best, (p - closest_point_on_triangle(p, m.vertices[t[0]], m.vertices[t[1]],
                                                         m.vertices[t[2]])).norm());
  }
  return best;
}

TEST(SignedDistanceGrid, ClosestPointOnTriangleRegions) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_TRUE(closest_point_on_triangle(Vec3(-1, -1, 0), a, b, c).isApprox(a));
  EXPECT_TRUE(closest_point_on_triangle(Vec3(2, -0.5, 0), a, b, c).isApprox(b));
  EXPECT_TRUE(closest_point_on_triangle(Vec3(0.5, -1, 3), a, b, c).isApprox(Vec3(0.5, 0, 0)));
  EXPECT_TRUE(closest_point_on_triangle(Vec3(1, 1, 0), a, b, c).isApprox(Vec3(0.5, 0.5, 0)));
  EXPECT_TRUE(closest_point_on_triangle(Vec3(0.2, 0.3, -2), a, b, c).isApprox(Vec3(0.2, 0.3, 0)));
}

TEST(SignedDistanceGrid, SphereDistancesSignsAndNormals) {
  const Vec3 centre(0.3 * kMm, -0.2 * kMm, 0.1 * kMm);
  const TriangleMesh m = make_sphere_mesh(centre, 4 * kMm, 3);
  SdfGridParams params;
  params.spacing_m = 0.25 * kMm;
  const SignedDistanceGrid g = SignedDistanceGrid::build(m, params);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-5.5 * kMm, 5.5 * kMm);
  for (int i = 0; i < 400; ++i) {
    const Vec3 p = centre + Vec3(u(rng), u(rng), u(rng));
    const double r = (p - centre).norm();
    const double exact = brute_distance(m, p);
    const double d = g.distance(p);
    // The polyhedron lies within 0.05 mm inside the sphere: signs are clear away from it.
    if (r < 3.8 * kMm) {
      EXPECT_LT(d, 0.0) << format_point_mm(p);
    }
    if (r > 4.1 * kMm) {
      EXPECT_GT(d, 0.0) << format_point_mm(p);
    }
    // Trilinear interpolation of the exact distance: errors a fraction of a cell.
    EXPECT_NEAR(std::abs(d), exact, 0.3 * params.spacing_m) << format_point_mm(p);
    if (std::abs(r - 4 * kMm) < 0.5 * kMm) {
      Vec3 n;
      g.distance(p, &n);
      EXPECT_GT(n.dot((p - centre).normalized()), std::cos(5.0 * std::numbers::pi / 180.0));
    }
  }
  // Outside the grid the value keeps growing with the distance.
  EXPECT_NEAR(g.distance(centre + Vec3(0, 0, 20 * kMm)), 16 * kMm, 0.3 * kMm);
}

TEST(SignedDistanceGrid, SignsAreRobustWhereTheSurfaceLiesOnGridPlanes) {
  // A box whose faces, edges and vertices lie exactly on grid planes and lines.
  const TriangleMesh box = make_box_mesh(Vec3(-1 * kMm, -1 * kMm, -1 * kMm), Vec3(1 * kMm, 1 * kMm, 1 * kMm));
  SdfGridParams params;
  params.spacing_m = 0.25 * kMm;
  params.margin_m = 1 * kMm;
  const SignedDistanceGrid g = SignedDistanceGrid::build(box, params);
  const auto& d = g.dims();
  int wrong = 0;
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i) {
        const Vec3 p = g.origin_m() + g.spacing_m() * Vec3(i, j, k);
        const double v = g.values()[(static_cast<std::size_t>(k) * d[1] + j) * d[0] + i];
        const Vec3 q = p.cwiseAbs() - Vec3::Constant(1 * kMm);
        const double exact = q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
        if (std::abs(exact) > 1e-9 && (v < 0) != (exact < 0)) ++wrong;
        EXPECT_NEAR(std::abs(v), std::abs(exact), 1e-6);
      }
  EXPECT_EQ(wrong, 0);
}

TEST(SignedDistanceGrid, TorusHoleIsOutside) {
  const double R = 4 * kMm, a = 1.5 * kMm;
  const auto torus = [&](const Vec3& p) { return std::hypot(std::hypot(p.x(), p.y()) - R, p.z()) - a; };
  const TriangleMesh m = extract_iso_surface(
      sample_function(torus, Vec3(-6.5 * kMm, -6.5 * kMm, -2.5 * kMm), Vec3(6.5 * kMm, 6.5 * kMm, 2.5 * kMm), 0.25 * kMm));
  SdfGridParams params;
  params.spacing_m = 0.3 * kMm;
  const SignedDistanceGrid g = SignedDistanceGrid::build(m, params);
  EXPECT_NEAR(g.distance(Vec3::Zero()), R - a, 0.05 * kMm);    // centre of the hole
  // Inside the ring, on its medial circle: the distance has a ridge there, which trilinear
  // interpolation rounds off by up to ~sqrt(3)/2 of a cell.
  EXPECT_NEAR(g.distance(Vec3(R, 0, 0)), -a, 0.9 * params.spacing_m);
  EXPECT_NEAR(g.distance(Vec3(0, -R, 0)), -a, 0.9 * params.spacing_m);
  EXPECT_NEAR(g.distance(Vec3(R + 0.8 * kMm, 0, 0)), -0.7 * kMm, 0.05 * kMm);
}

TEST(SignedDistanceGrid, ClippedGridAgreesWithTheFullGrid) {
  const TriangleMesh m = make_sphere_mesh(Vec3::Zero(), 4 * kMm, 3);
  SdfGridParams full;
  full.spacing_m = 0.25 * kMm;
  SdfGridParams clip = full;
  clip.clip = true;
  clip.clip_min_m = Vec3(-1 * kMm, -1 * kMm, 2 * kMm);
  clip.clip_max_m = Vec3(1 * kMm, 1 * kMm, 5 * kMm);
  const SignedDistanceGrid a = SignedDistanceGrid::build(m, full), b = SignedDistanceGrid::build(m, clip);
  EXPECT_LT(b.values().size(), a.values().size() / 4);
  EXPECT_NE(a.key(), b.key());
  for (double z : {2.0, 3.0, 3.9, 4.1, 5.0}) {
    const Vec3 p(0.3 * kMm, -0.2 * kMm, z * kMm);
    EXPECT_NEAR(a.distance(p), b.distance(p), 1e-6) << z;
  }
}

TEST(SignedDistanceGrid, GradientBoundHoldsBetweenLookupsInsideAndOutsideTheGrid) {
  const TriangleMesh m = make_sphere_mesh(Vec3::Zero(), 3 * kMm, 2);
  SdfGridParams params;
  params.spacing_m = 0.25 * kMm;
  params.clip = true;  // so that some points lie outside the grid's box
  params.clip_min_m = Vec3(-1 * kMm, -1 * kMm, 1 * kMm);
  params.clip_max_m = Vec3(1 * kMm, 1 * kMm, 4 * kMm);
  const SignedDistanceGrid g = SignedDistanceGrid::build(m, params);
  const double L = g.gradient_bound();
  // Samples of a distance differ by at most a spacing along each axis, so the bound is at
  // most sqrt(3) (reached in cells across the sphere's centre, where the distance has a
  // kink) and at least 1 (the distance's own slope).
  EXPECT_GE(L, 0.99);
  EXPECT_LE(L, std::sqrt(3.0) * 1.001);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-4 * kMm, 6 * kMm), step(-0.4 * kMm, 0.4 * kMm);
  double worst = 0.0;
  for (int t = 0; t < 20000; ++t) {
    const Vec3 p(u(rng) * 0.5, u(rng) * 0.5, u(rng));
    const Vec3 q = p + Vec3(step(rng), step(rng), step(rng));
    const double r = (p - q).norm();
    if (r <= 0.0) continue;
    const double slope = std::abs(g.distance(p) - g.distance(q)) / r;
    worst = std::max(worst, slope);
    ASSERT_LE(slope, L + 1.0 + 1e-9) << t;  // inside the box L, beyond it one more
  }
  EXPECT_GT(worst, 0.5);  // the samples did test something
  // A loaded grid has the same bound.
  std::string error;
  const auto loaded = SignedDistanceGrid::deserialize(g.serialize(), &error);
  ASSERT_TRUE(loaded) << error;
  EXPECT_EQ(loaded->gradient_bound(), L);
}

TEST(SignedDistanceGrid, LookupsDoNotAllocate) {
  const TriangleMesh m = make_sphere_mesh(Vec3::Zero(), 3 * kMm, 2);
  const SignedDistanceGrid g = SignedDistanceGrid::build(m, SdfGridParams{});
  double sum = 0.0;
  Vec3 n;
  const long before = test_support::heap_allocations();
  for (int i = 0; i < 1000; ++i) sum += g.distance(Vec3(1e-5 * i, 2e-6 * i, -3e-6 * i), &n);
  EXPECT_EQ(test_support::heap_allocations(), before);
  EXPECT_TRUE(std::isfinite(sum));
}

TEST(SignedDistanceGrid, CacheBuildsOnceThenLoadsTheSameGrid) {
  const auto dir = (std::filesystem::temp_directory_path() / "acdr_sdf_cache_test").string();
  std::filesystem::remove_all(dir);
  const TriangleMesh m = make_sphere_mesh(Vec3::Zero(), 3 * kMm, 2);
  SdfGridParams params;
  params.spacing_m = 0.3 * kMm;
  SdfLoadInfo first, second, other;
  const SignedDistanceGrid a = build_or_load_sdf(m, params, dir, &first);
  const SignedDistanceGrid b = build_or_load_sdf(m, params, dir, &second);
  EXPECT_FALSE(first.from_cache) << first.note;
  EXPECT_TRUE(second.from_cache) << second.note;
  EXPECT_EQ(first.cache_path, second.cache_path);
  ASSERT_EQ(a.values().size(), b.values().size());
  EXPECT_TRUE(std::equal(a.values().begin(), a.values().end(), b.values().begin()));
  // Other parameters, other file.
  params.spacing_m = 0.35 * kMm;
  build_or_load_sdf(m, params, dir, &other);
  EXPECT_FALSE(other.from_cache);
  EXPECT_NE(other.cache_path, first.cache_path);

  // A damaged file is not trusted: rebuilt and said so.
  params.spacing_m = 0.3 * kMm;
  std::string error;
  ASSERT_TRUE(write_cache_file(first.cache_path, "ACDRSDF", &error)) << error;
  SdfLoadInfo third;
  const SignedDistanceGrid c = build_or_load_sdf(m, params, dir, &third);
  EXPECT_FALSE(third.from_cache);
  EXPECT_NE(third.note.find("ignored (shorter than the header"), std::string::npos) << third.note;
  EXPECT_EQ(c.values().size(), a.values().size());
  std::filesystem::remove_all(dir);
}

TEST(SignedDistanceGrid, DeserializeRefusesTruncatedFiles) {
  const SignedDistanceGrid g = SignedDistanceGrid::build(make_box_mesh(Vec3::Zero(), Vec3::Constant(1 * kMm)), SdfGridParams{});
  std::string bytes = g.serialize();
  std::string error;
  EXPECT_TRUE(SignedDistanceGrid::deserialize(bytes, &error));
  bytes.resize(bytes.size() - 4);
  EXPECT_FALSE(SignedDistanceGrid::deserialize(bytes, &error));
  EXPECT_NE(error.find("truncated"), std::string::npos) << error;
}

}  // namespace
}  // namespace acdr
