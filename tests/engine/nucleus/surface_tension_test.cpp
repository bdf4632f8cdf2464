// Surface tension between torn faces (engine/nucleus/surface_tension.hpp): the pair law does
// the work of two faces and is the slope of its potential; two pieces of a material with a
// surface tension, a gap between them, pull together while the mechanical energy (which
// includes the pair potential) only falls; without it they stay apart; a step with it on
// allocates nothing.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "engine/nucleus/nucleus.hpp"
#include "engine/nucleus/surface_tension.hpp"
#include "tests/engine/nucleus/nucleus_test_scenes.hpp"
#include "verification/box_block_scene.hpp"

namespace acdr {
namespace {

using nucleus::surface_tension_energy;
using nucleus::surface_tension_force;
using nucleus::surface_tension_peak_force;

constexpr double kH = 1e-3;
constexpr double kR = 1.5e-3;  // the reach: the bond radius at h = 1 mm (factor 1.5)
constexpr double kWater = 0.070;  // N/m at 37 degC

TEST(SurfaceTension, PairLawDoesTheWorkOfTwoFacesAndIsTheSlopeOfItsPotential) {
  const double peak = surface_tension_peak_force(kWater, kH, kR);
  // Work of pulling a pair from h to R: Simpson's rule on 2000 intervals.
  const int n = 2000;
  const double step = (kR - kH) / n;
  double work = 0.0;
  for (int k = 0; k <= n; ++k) {
    const double r = kH + k * step;
    const double w = (k == 0 || k == n) ? 1.0 : (k % 2 ? 4.0 : 2.0);
    work += w * surface_tension_force(r, kH, kR, peak).force;
  }
  work *= step / 3.0;
  const double faces = 2.0 * kWater * kH * kH;
  std::printf("work of separation %.6e J, two faces of h^2 %.6e J\n", work, faces);
  EXPECT_NEAR(work, faces, 1e-9 * faces);
  EXPECT_NEAR(surface_tension_energy(kH, kH, kR, peak), -faces, 1e-12 * faces);
  // F = -dU/dr and F' = dF/dr by central differences, at points across (h, R).
  for (double s : {0.05, 0.3, 0.5, 0.7, 0.95}) {
    const double r = kH + s * (kR - kH), d = 1e-9;
    const auto t = surface_tension_force(r, kH, kR, peak);
    const double slope_u = (surface_tension_energy(r + d, kH, kR, peak) -
                            surface_tension_energy(r - d, kH, kR, peak)) / (2 * d);
    const double slope_f = (surface_tension_force(r + d, kH, kR, peak).force -
                            surface_tension_force(r - d, kH, kR, peak).force) / (2 * d);
    EXPECT_NEAR(t.force, slope_u, 1e-5 * peak) << "at s = " << s;
    EXPECT_NEAR(t.stiffness, slope_f, 1e-5 * peak / (kR - kH)) << "at s = " << s;
  }
  // Nothing at or inside the spacing, at or beyond R, nor without room between them.
  EXPECT_EQ(surface_tension_force(kH, kH, kR, peak).force, 0.0);
  EXPECT_EQ(surface_tension_force(0.5 * kH, kH, kR, peak).force, 0.0);
  EXPECT_EQ(surface_tension_force(kR, kH, kR, peak).force, 0.0);
  EXPECT_EQ(surface_tension_energy(kR, kH, kR, peak), 0.0);
  EXPECT_EQ(surface_tension_peak_force(kWater, kH, kH), 0.0);
  EXPECT_EQ(surface_tension_peak_force(0.0, kH, kR), 0.0);
}

test::TwoPieces two_pieces(double gamma_N_m, double gap) {
  MaterialConfig m;
  m.surface_tension_N_m = gamma_N_m;
  return test::two_pieces(m, kH, gap);
}

TEST(SurfaceTension, PiecesWithAGapPullTogetherWhileTheEnergyFalls) {
  const test::TwoPieces s = two_pieces(kWater, 1.3 * kH);
  Nucleus n(s.config, s.solver, Vec3::Zero(), {}, s.setup);
  const double start = n.positions()[s.right[0]].x() - n.positions()[s.left[4]].x();
  double energy = n.mechanical_energy_J();
  const double energy_start = energy;
  double rise = 0.0;
  for (int step = 0; step < 1000; ++step) {
    NumericalReport r;
    n.step(1e-3, {}, {}, r);
    ASSERT_TRUE(r.ok) << r.stage;
    const double e = n.mechanical_energy_J();
    rise = std::max(rise, e - energy);
    energy = e;
  }
  const double end = n.positions()[s.right[0]].x() - n.positions()[s.left[4]].x();
  std::printf("facing layers %.3f mm apart at the start, %.3f mm after 1 s; energy %.4e -> "
              "%.4e J, largest rise in a step %.2e J\n",
              start * 1e3, end * 1e3, energy_start, energy, rise);
  EXPECT_NEAR(start, 1.3 * kH, 1e-12);
  // Drawn in to about a spacing (the offset pairs pull a little closer, the pressure holds).
  EXPECT_LT(end, 1.1 * kH);
  EXPECT_GT(end, 0.5 * kH);
  EXPECT_LT(energy, energy_start - 1e-8);  // some of 4 pairs x 2 gamma h^2 released
  EXPECT_LE(rise, 1e-6 * std::abs(energy_start));
}

TEST(SurfaceTension, WithoutItPiecesWithAGapStayApart) {
  const test::TwoPieces s = two_pieces(0.0, 1.3 * kH);
  Nucleus n(s.config, s.solver, Vec3::Zero(), {}, s.setup);
  for (int step = 0; step < 100; ++step) {
    NumericalReport r;
    n.step(1e-3, {}, {}, r);
    ASSERT_TRUE(r.ok) << r.stage;
  }
  EXPECT_NEAR(n.positions()[s.right[0]].x() - n.positions()[s.left[4]].x(), 1.3 * kH, 1e-9);
}

TEST(SurfaceTension, StepWithSurfaceTensionDoesNotAllocate) {
  BoxBlockScene scene = make_box_block_scene(2e-3);
  scene.nucleus.materials[0].surface_tension_N_m = 0.2;
  Nucleus n(scene.nucleus, scene.solver, scene.gravity, scene.statics);
  bool ok = false;
  EXPECT_EQ(test::heap_allocations_while_cutting(n, scene.blade, 100, &ok), 0);
  EXPECT_TRUE(ok);
  EXPECT_GT(n.broken_bond_count(), 0u);
}

}  // namespace
}  // namespace acdr
