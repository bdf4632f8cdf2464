// Device safety rules: NaN and jump rejection, target slew, force ramp, clamp and rate limit.
#include "engine/devices/device_guard.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace acdr {
namespace {

DeviceConfig touch() {
  DeviceConfig d;
  d.max_force_N = 3.3;
  d.max_force_rate_N_s = 300.0;
  d.ramp_in_s = 0.1;
  d.max_jump_m = 0.01;
  return d;
}

TEST(DeviceGuard, RejectsNonFinitePoses) {
  DeviceGuard g(touch(), Pose{}, 1e-3);
  Pose bad;
  bad.position.x() = std::numeric_limits<double>::quiet_NaN();
  const GuardedInput in = g.accept(bad);
  EXPECT_FALSE(in.accepted);
  EXPECT_TRUE(in.non_finite);
  EXPECT_TRUE(in.target.position.allFinite());
  // While rejecting, no force goes out.
  EXPECT_EQ(g.limit(Vec3(1, 0, 0), 1.0).force_N, Vec3::Zero());
}

TEST(DeviceGuard, RejectsJumpUntilSettledThenSlews) {
  DeviceGuard g(touch(), Pose{}, 1e-3);
  Pose far;
  far.position = Vec3(0.05, 0, 0);  // a 5 cm teleport
  for (int i = 0; i < DeviceGuard::kSettleSamples - 1; ++i) {
    const GuardedInput in = g.accept(far);
    EXPECT_FALSE(in.accepted);
    EXPECT_NEAR(in.jump_m, 0.05, 1e-12);
  }
  const GuardedInput in = g.accept(far);
  EXPECT_TRUE(in.accepted);
  // The target moves toward the new place at the bounded speed, not at once.
  EXPECT_NEAR(in.target.position.x(), DeviceGuard::kMaxTargetSpeed * 1e-3, 1e-12);
  EXPECT_NEAR(in.target_velocity.norm(), DeviceGuard::kMaxTargetSpeed, 1e-9);
}

TEST(DeviceGuard, RampsInClampsAndRateLimits) {
  DeviceGuard g(touch(), Pose{}, 1e-3);
  g.accept(Pose{});
  // At t = 0 the ramp is at zero.
  EXPECT_EQ(g.limit(Vec3(2, 0, 0), 0.0).force_N.norm(), 0.0);
  // Far past the ramp, a large request is clamped to 3.3 N, reached at 300 N/s at most.
  double last = 0;
  GuardedForce out;
  for (int i = 1; i <= 200; ++i) {
    out = g.limit(Vec3(100, 0, 0), 0.2 + i * 1e-3);
    EXPECT_LE(out.force_N.norm() - last, 300.0 * 1e-3 + 1e-12);
    EXPECT_LE(out.force_N.norm(), 3.3 + 1e-12);
    last = out.force_N.norm();
  }
  EXPECT_TRUE(out.clamped);
  EXPECT_NEAR(out.force_N.norm(), 3.3, 1e-12);
  EXPECT_NEAR(out.requested_N, 100.0, 1e-12);
}

TEST(DeviceGuard, LostInputHoldsTheTargetZeroesTheForceAndRampsInAgain) {
  DeviceGuard g(touch(), Pose{}, 1e-3);
  Pose p;
  p.position = Vec3(0.001, 0, 0);
  g.accept(p);
  double t = 1.0;
  for (int i = 0; i < 50; ++i) g.limit(Vec3(2, 0, 0), t += 1e-3);  // settled at 2 N
  // The device goes silent: the target holds still, no velocity, and the force falls to zero
  // within the rate limit (2 N at 300 N/s: under 7 ms).
  GuardedInput held = g.accept_lost();
  EXPECT_FALSE(held.accepted);
  EXPECT_EQ(held.target_velocity, Vec3::Zero());
  const Vec3 target = held.target.position;
  GuardedForce f;
  for (int i = 0; i < 10; ++i) {
    held = g.accept_lost();
    EXPECT_EQ(held.target.position, target);
    f = g.limit(Vec3(2, 0, 0), t += 1e-3);
  }
  EXPECT_EQ(f.force_N, Vec3::Zero());
  // Data returns: the force ramps in from zero again (ramp_in_s = 0.1 s), no kick.
  g.accept(p);
  f = g.limit(Vec3(2, 0, 0), t += 1e-3);
  EXPECT_LT(f.force_N.norm(), 0.05);
  for (int i = 0; i < 200; ++i) {
    g.accept(p);
    f = g.limit(Vec3(2, 0, 0), t += 1e-3);
  }
  EXPECT_NEAR(f.force_N.norm(), 2.0, 1e-9);
}

}  // namespace
}  // namespace acdr
