// Tests of engine/haptic_local_model: between physics steps the device feels the physics force
// corrected through the coupling spring, limited like the World's output, and nothing when
// its data cannot be trusted.
#include "engine/devices/haptic_local_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace acdr {
namespace {

DeviceConfig touch() {
  DeviceConfig d;  // Touch: 3.3 N, 300 N/s, 10 mm jump threshold
  return d;
}

PhysicsForce physics(const Vec3& f, const Vec3& x) {
  PhysicsForce p;
  p.force_N = f;
  p.device_position_m = x;
  p.valid = true;
  return p;
}

TEST(HapticLocalModel, AddsTheCouplingSpringForTheHandsMotionSinceTheStep) {
  // k = 500 N/m, 1 kHz; slew 300 N/s allows 0.3 N per tick, so start from the physics force.
  HapticLocalModel model(touch(), 500.0, 1e-3);
  const Vec3 x0(0.01, 0.0, 0.1);
  const PhysicsForce p = physics(Vec3(0.0, 0.0, 0.2), x0);
  LocalForce f = model.force(p, x0, false);
  EXPECT_NEAR(f.force_N.z(), 0.2, 1e-12);  // no motion: the physics force (0.2 < 0.3 slew)
  // The hand moves 0.2 mm down: the spring pushes back up by k dx = 0.1 N.
  f = model.force(p, x0 + Vec3(0, 0, -0.0002), false);
  EXPECT_NEAR(f.force_N.z(), 0.2 + 500.0 * 0.0002, 1e-12);
  EXPECT_NEAR(f.force_N.x(), 0.0, 1e-15);
  EXPECT_FALSE(f.clamped);
  EXPECT_FALSE(f.zeroed);
}

TEST(HapticLocalModel, ClampsToTheDeviceMaximumAndSlewsAtItsRate) {
  HapticLocalModel model(touch(), 500.0, 1e-3);
  const Vec3 x0 = Vec3::Zero();
  // 10 N requested: rises 0.3 N per tick (300 N/s x 1 ms), stops at 3.3 N.
  const PhysicsForce p = physics(Vec3(10.0, 0.0, 0.0), x0);
  double last = 0.0;
  for (int k = 1; k <= 20; ++k) {
    const LocalForce f = model.force(p, x0, false);
    EXPECT_TRUE(f.clamped);
    EXPECT_NEAR(f.force_N.x(), std::min(0.3 * k, 3.3), 1e-9) << "tick " << k;
    EXPECT_LE(f.force_N.norm(), 3.3);  // never above the rating, not even by rounding
    last = f.force_N.x();
  }
  EXPECT_NEAR(last, 3.3, 1e-9);
}

TEST(HapticLocalModel, ZeroForStaleNonFiniteJumpedOrMissingData) {
  HapticLocalModel model(touch(), 500.0, 1e-3);
  const Vec3 x0 = Vec3::Zero();
  const PhysicsForce p = physics(Vec3(0.0, 0.0, 0.25), x0);
  ASSERT_GT(model.force(p, x0, false).force_N.norm(), 0.0);
  EXPECT_TRUE(model.force(p, x0, true).zeroed);  // stale
  const double nan = std::numeric_limits<double>::quiet_NaN();
  LocalForce f = model.force(p, Vec3(nan, 0, 0), false);
  EXPECT_TRUE(f.zeroed);
  EXPECT_EQ(f.force_N, Vec3::Zero());
  f = model.force(p, Vec3(0.011, 0, 0), false);  // 11 mm from the step's pose: a jump
  EXPECT_TRUE(f.zeroed);
  EXPECT_TRUE(model.force(PhysicsForce{}, x0, false).zeroed);  // no physics step yet
  // Good data again: the force comes back through the slew limit, from zero.
  f = model.force(p, x0, false);
  EXPECT_FALSE(f.zeroed);
  EXPECT_NEAR(f.force_N.z(), 0.25, 1e-12);
}

}  // namespace
}  // namespace acdr
