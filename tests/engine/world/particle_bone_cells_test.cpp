// The particles' reaction on the bone gathered per cell: each particle on the nearer vertebra,
// the force summed per cell at the force-weighted mean of its particles, and the total force
// kept when the cells do not all fit (gathering or appending to a sample with little room).
#include "engine/world/particle_bone_cells.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "engine/geometry/mesh_shapes.hpp"
#include "engine/geometry/signed_distance_grid.hpp"

namespace acdr {
namespace {

struct Slabs {
  SignedDistanceGrid c4, c5;  // a slab above z = 3 mm and one below z = -3 mm
  Slabs() {
    SdfGridParams p;
    p.spacing_m = 0.5e-3;
    c4 = SignedDistanceGrid::build(make_box_mesh(Vec3(-0.01, -0.01, 0.003), Vec3(0.01, 0.01, 0.006)), p);
    c5 = SignedDistanceGrid::build(make_box_mesh(Vec3(-0.01, -0.01, -0.006), Vec3(0.01, 0.01, -0.003)), p);
  }
};

// Particles on a 0.5 mm lattice filling [-4, 4) mm x [-4, 4) mm at z = +-2.5 mm, each pushing
// on the slab it is nearest with a force of 1 + i mN.
void particles(std::vector<Vec3>& x, std::vector<Vec3>& f) {
  for (int i = 0; i < 16; ++i)
    for (int j = 0; j < 16; ++j)
      for (const double z : {2.5e-3, -2.5e-3}) {
        x.emplace_back(-4e-3 + 0.5e-3 * i, -4e-3 + 0.5e-3 * j, z);
        f.emplace_back(0.0, 0.0, (z > 0 ? 1.0 : -1.0) * 1e-3 * (1.0 + i));
      }
  x.emplace_back(0.0, 0.0, 0.0);  // no force: not a load
  f.emplace_back(0.0, 0.0, 0.0);
}

// The particles above gathered on the slabs into cells of `cell_m`, at most `capacity`.
ParticleBoneCells gathered(double cell_m, int capacity) {
  const Slabs slabs;
  std::vector<Vec3> x, f;
  particles(x, f);
  ParticleBoneCells cells;
  cells.gather(f, x, slabs.c4, slabs.c5, cell_m, capacity);
  return cells;
}

Vec3 total(const BoneLoadSample& s, int from) {
  Vec3 t = Vec3::Zero();
  for (int k = from; k < s.count; ++k) t += s.points[k].force_N.cast<double>();
  return t;
}

TEST(ParticleBoneCells, EachCellOnItsVertebraAtTheWeightedMean) {
  const ParticleBoneCells cells = gathered(2e-3, ParticleBoneCells::kCapacity);
  // 4 x 4 cells of 2 mm in x and y, on each of the two vertebrae.
  ASSERT_EQ(cells.count, 32);
  BoneLoadSample s;
  cells.append_to(s);
  ASSERT_EQ(s.count, 32);
  Vec3 f_c4 = Vec3::Zero(), f_c5 = Vec3::Zero();
  for (int k = 0; k < s.count; ++k) {
    const BoneLoadPoint& p = s.points[k];
    EXPECT_EQ(p.source, BoneLoadSource::kNucleus);
    EXPECT_FLOAT_EQ(p.radius_m, 1e-3f);
    (p.vertebra == 0 ? f_c4 : f_c5) += p.force_N.cast<double>();
    EXPECT_EQ(p.vertebra, p.point_m.z() > 0 ? 0 : 1) << "cell " << k;
  }
  // The C4 cell of x, y in [-4, -2) mm: forces 1-4 mN at x = -4, -3.5, -3, -2.5 mm (every y):
  // weighted mean x = (1 (-4) + 2 (-3.5) + 3 (-3) + 4 (-2.5)) / 10 = -3 mm, y the plain mean
  // of -4, -3.5, -3 and -2.5 mm, -3.25 mm.
  int corner = 0;
  for (int k = 0; k < s.count; ++k) {
    const BoneLoadPoint& p = s.points[k];
    if (p.vertebra != 0 || p.point_m.x() > -2e-3f || p.point_m.y() > -2e-3f) continue;
    ++corner;
    EXPECT_NEAR(p.point_m.x(), -3.0e-3, 1e-7);
    EXPECT_NEAR(p.point_m.y(), -3.25e-3, 1e-7);
    EXPECT_NEAR(p.point_m.z(), 2.5e-3, 1e-7);
    EXPECT_NEAR(p.force_N.z(), 4 * (1 + 2 + 3 + 4) * 1e-3, 1e-7);
  }
  EXPECT_EQ(corner, 1);
  double expected = 0.0;  // 16 rows j of sum over i of (1 + i) mN per slab
  for (int i = 0; i < 16; ++i) expected += 16 * 1e-3 * (1.0 + i);
  EXPECT_NEAR(f_c4.z(), expected, 1e-6);
  EXPECT_NEAR(f_c5.z(), -expected, 1e-6);
}

// A sample that already holds instrument points has room for fewer cells: the ones beyond it
// join the nearest kept cell of their vertebra, so each vertebra's total force is kept.
TEST(ParticleBoneCells, CellsBeyondTheRoomJoinTheNearestAndKeepTheForce) {
  const ParticleBoneCells cells = gathered(1e-3, ParticleBoneCells::kCapacity);
  ASSERT_EQ(cells.count, 128);  // 8 x 8 cells of 1 mm on each vertebra
  BoneLoadSample all, tight;
  cells.append_to(all);
  tight.count = BoneLoadSample::kCapacity - 20;  // instrument points already there
  cells.append_to(tight);
  EXPECT_EQ(tight.count, BoneLoadSample::kCapacity);
  const Vec3 t_all = total(all, 0), t_tight = total(tight, BoneLoadSample::kCapacity - 20);
  EXPECT_NEAR(t_tight.z(), t_all.z(), 1e-6);
  // Per vertebra too: a cell only ever joins one of its own.
  double c4_all = 0.0, c4_tight = 0.0;
  for (int k = 0; k < all.count; ++k)
    if (all.points[k].vertebra == 0) c4_all += all.points[k].force_N.z();
  for (int k = BoneLoadSample::kCapacity - 20; k < tight.count; ++k)
    if (tight.points[k].vertebra == 0) c4_tight += tight.points[k].force_N.z();
  EXPECT_NEAR(c4_tight, c4_all, 1e-6);
  // Gathering into fewer cells than it needs keeps the force the same way.
  const ParticleBoneCells few = gathered(1e-3, 20);
  EXPECT_EQ(few.count, 20);
  BoneLoadSample s;
  few.append_to(s);
  EXPECT_NEAR(total(s, 0).z(), t_all.z(), 1e-6);
}

}  // namespace
}  // namespace acdr
