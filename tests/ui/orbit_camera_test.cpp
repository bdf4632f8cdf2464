// Tests of ui/orbit_camera: it starts where the given camera is, orbits around the target,
// zooms toward it, pans the target, and never flips over the pole.
#include "ui/orbit_camera.hpp"

#include <gtest/gtest.h>

namespace acdr {
namespace {

TEST(OrbitCamera, StartsWhereTheGivenCameraIs) {
  RenderCamera c;
  c.eye = Eigen::Vector3f(0.06f, -0.08f, 0.07f);
  c.target = Eigen::Vector3f(0.01f, 0.0f, 0.005f);
  const OrbitCamera orbit(c);
  EXPECT_TRUE(orbit.camera().eye.isApprox(c.eye, 1e-5f));
  EXPECT_TRUE(orbit.camera().target.isApprox(c.target));
}

TEST(OrbitCamera, OrbitsZoomsAndPans) {
  RenderCamera c;
  c.eye = Eigen::Vector3f(0, -0.1f, 0);
  OrbitCamera orbit(c);
  orbit.orbit(100, 0, 0.0157079633f);  // 90 degrees of yaw
  EXPECT_NEAR((orbit.camera().eye - c.target).norm(), 0.1f, 1e-6f);
  EXPECT_NEAR(std::abs(orbit.camera().eye.x()), 0.1f, 1e-5f);
  orbit.zoom(1);
  EXPECT_NEAR(orbit.distance(), 0.088f, 1e-6f);
  const Eigen::Vector3f before = orbit.target();
  orbit.pan(50, 0, 500);
  EXPECT_GT((orbit.target() - before).norm(), 1e-4f);
  EXPECT_NEAR(orbit.target().z(), before.z(), 1e-6f);  // a horizontal drag stays level
  orbit.orbit(0, 100000);
  EXPECT_LT(orbit.pitch(), 1.5f);  // clamped short of the pole
}

}  // namespace
}  // namespace acdr
