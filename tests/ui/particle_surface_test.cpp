// Particle surfaces: a lone particle is a small sphere, a lattice block a closed slab just
// beyond its centres, pieces far apart stay apart, and the grid stays within its budget.
#include "ui/particle_surface.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <utility>

namespace acdr {
namespace {

// Every edge shared by exactly two triangles, in opposite directions: closed and oriented.
bool closed_and_oriented(const ParticleSurface& s) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  for (std::size_t t = 0; t + 2 < s.indices.size(); t += 3)
    for (int e = 0; e < 3; ++e) ++edges[{s.indices[t + e], s.indices[t + (e + 1) % 3]}];
  for (const auto& [edge, count] : edges) {
    if (count != 1) return false;
    const auto back = edges.find({edge.second, edge.first});
    if (back == edges.end() || back->second != 1) return false;
  }
  return !edges.empty();
}

TEST(ParticleSurface, NoParticlesNoSurface) {
  EXPECT_TRUE(particle_surface({}, 1e-3f).indices.empty());
}

TEST(ParticleSurface, ALoneParticleIsASphereOfItsRadius) {
  const float h = 2e-3f;
  const Eigen::Vector3f c(0.01f, -0.02f, 0.003f);
  const std::vector<Eigen::Vector3f> one = {c};
  const ParticleSurfaceOptions o;
  const ParticleSurface s = particle_surface(one, h, o);
  ASSERT_FALSE(s.indices.empty());
  EXPECT_TRUE(closed_and_oriented(s));
  ASSERT_EQ(s.normals.size(), s.vertices.size());
  // A sphere of 1.2 cells is sampled coarsely: the crossings on the grid's long edges are chords,
  // inside the sphere (the distance is convex along an edge), by up to about a third of a cell.
  const float r = o.radius_spacings * h;
  double mean = 0.0;
  for (std::size_t v = 0; v < s.vertices.size(); ++v) {
    const Eigen::Vector3f d = s.vertices[v] - c;
    EXPECT_GT(d.norm(), r - 0.4f * o.cell_spacings * h);
    EXPECT_LT(d.norm(), r + 0.02f * h);
    EXPECT_GT(s.normals[v].dot(d.normalized()), 0.98f);  // pointing away from the centre
    mean += d.norm() / s.vertices.size();
  }
  EXPECT_NEAR(mean, r, 0.12 * r);
}

TEST(ParticleSurface, ALatticeBlockIsOneSlabJustBeyondItsCentres) {
  const float h = 1e-3f;
  std::vector<Eigen::Vector3f> block;
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 8; ++i) block.emplace_back(i * h, j * h, k * h);
  const ParticleSurface s = particle_surface(block, h);
  EXPECT_TRUE(closed_and_oriented(s));
  Eigen::Vector3f lo = s.vertices[0], hi = s.vertices[0];
  for (const Eigen::Vector3f& v : s.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  const float r = ParticleSurfaceOptions{}.radius_spacings * h;
  const Eigen::Vector3f want_lo = Eigen::Vector3f::Constant(-r);
  const Eigen::Vector3f want_hi = Eigen::Vector3f(7 * h + r, 4 * h + r, 3 * h + r);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(lo[a], want_lo[a], 0.25f * h) << a;
    EXPECT_NEAR(hi[a], want_hi[a], 0.25f * h) << a;
  }
  // The top face is flat: its vertices over the middle of the block face straight up.
  int top = 0;
  for (std::size_t v = 0; v < s.vertices.size(); ++v) {
    const Eigen::Vector3f& p = s.vertices[v];
    if (p.z() > 3 * h + 0.5f * r && p.x() > 2 * h && p.x() < 5 * h && p.y() > 1.5f * h &&
        p.y() < 2.5f * h) {
      ++top;
      EXPECT_NEAR(p.z(), 3 * h + r, 0.1f * h);
      EXPECT_GT(s.normals[v].z(), 0.99f);
    }
  }
  EXPECT_GT(top, 5);
}

// Connected pieces of the triangle mesh.
int components(const ParticleSurface& s) {
  std::vector<std::uint32_t> parent(s.vertices.size());
  for (std::uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
  auto root = [&](std::uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (std::size_t t = 0; t + 2 < s.indices.size(); t += 3)
    for (int e = 1; e < 3; ++e) parent[root(s.indices[t + e])] = root(s.indices[t]);
  int n = 0;
  for (std::uint32_t i = 0; i < parent.size(); ++i) n += root(i) == i;
  return n;
}

TEST(ParticleSurface, ParticlesJoinOnlyWithinTheJoinDistance) {
  const float h = 1e-3f;
  const float join = ParticleSurfaceOptions{}.join_spacings;
  const std::vector<Eigen::Vector3f> near = {{0, 0, 0}, {0.9f * join * h, 0, 0}};
  // The gap must be wider than a grid cell to be seen: join + 1.5 cells apart.
  const float gap = (join + 1.5f * ParticleSurfaceOptions{}.cell_spacings) * h;
  const std::vector<Eigen::Vector3f> apart = {{0, 0, 0}, {gap, 0, 0}};
  EXPECT_EQ(components(particle_surface(near, h)), 1);
  EXPECT_EQ(components(particle_surface(apart, h)), 2);
}

TEST(ParticleSurface, PiecesFarApartStayApartAndTheGridKeepsItsBudget) {
  const float h = 1e-3f;
  const std::vector<Eigen::Vector3f> two = {{0, 0, 0}, {5 * h, 0, 0}};
  const ParticleSurface s = particle_surface(two, h);
  for (const Eigen::Vector3f& v : s.vertices)
    EXPECT_LT(std::min((v - two[0]).norm(), (v - two[1]).norm()), 0.7f * h);
  // Spread over a metre: cells grow so the grid stays within its point budget.
  ParticleSurfaceOptions o;
  o.max_grid_points = 200000;
  const std::vector<Eigen::Vector3f> spread = {{0, 0, 0}, {1.0f, 0.5f, 0.2f}};
  const ParticleSurface wide = particle_surface(spread, h, o);
  EXPECT_LE(wide.grid_points, o.max_grid_points);
  EXPECT_GT(wide.cell_m, o.cell_spacings * h);
}

}  // namespace
}  // namespace acdr
