// Tests of ui/mouse_instrument: the documented mapping (docs/trainee-view.md), relative to
// the view, speed-limited; and the device hands the newest pose to the haptic thread.
#include "ui/mouse_instrument.hpp"

#include <gtest/gtest.h>

namespace acdr {
namespace {

// A camera behind the work area looking along +y (screen right = +x, away = +y).
RenderCamera looking_north() {
  RenderCamera c;
  c.eye = Eigen::Vector3f(0, -0.2f, 0.1f);
  c.target = Eigen::Vector3f::Zero();
  return c;
}

TEST(MouseInstrument, DragsMoveInTheViewsHorizontalPlane) {
  const Pose start;
  MouseKeyInput in;
  in.drag_dx_px = 10;  // right
  Pose p = apply_mouse_input(start, in, looking_north());
  EXPECT_NEAR(p.position.x(), 10 * 0.1e-3, 1e-12);
  EXPECT_NEAR(p.position.y(), 0, 1e-12);
  EXPECT_NEAR(p.position.z(), 0, 1e-12);
  in = {};
  in.drag_dy_px = -10;  // up on the screen: away from the viewer
  p = apply_mouse_input(start, in, looking_north());
  EXPECT_NEAR(p.position.y(), 1e-3, 1e-12);
  EXPECT_NEAR(p.position.z(), 0, 1e-12);
  // A camera looking along +x turns the same drag into +x motion away from it.
  RenderCamera east = looking_north();
  east.eye = Eigen::Vector3f(-0.2f, 0, 0.1f);
  p = apply_mouse_input(start, in, east);
  EXPECT_NEAR(p.position.x(), 1e-3, 1e-9);
}

TEST(MouseInstrument, KeysRaiseLowerAndTiltAtTheirSpeeds) {
  const Pose start;
  MouseKeyInput in;
  in.up = true;
  in.dt_s = 0.1;
  EXPECT_NEAR(apply_mouse_input(start, in, looking_north()).position.z(), 0.002, 1e-12);
  in.fast = true;
  EXPECT_NEAR(apply_mouse_input(start, in, looking_north()).position.z(), 0.004, 1e-12);  // capped
  in = {};
  in.tilt_plus = true;
  in.dt_s = 0.5;
  const Pose tilted = apply_mouse_input(start, in, looking_north());
  // 0.8 rad/s for 0.5 s about the view's right axis (x): the shaft axis leaves the vertical.
  EXPECT_NEAR(start.orientation.angularDistance(tilted.orientation), 0.4, 1e-9);
  const Vec3 axis = tilted.orientation * Vec3::UnitZ();
  EXPECT_NEAR(axis.x(), 0.0, 1e-9);
  EXPECT_GT(std::abs(axis.y()), 0.3);
}

TEST(MouseInstrument, OneFrameCannotTeleportAndHoldFreezes) {
  const Pose start;
  MouseKeyInput in;
  in.drag_dx_px = 5000;
  EXPECT_NEAR(apply_mouse_input(start, in, looking_north()).position.norm(), 4e-3, 1e-12);
  in.hold = true;
  EXPECT_EQ(apply_mouse_input(start, in, looking_north()).position, start.position);
}

TEST(MouseInstrument, DeviceGivesTheNewestPoseAndTheEnd) {
  Pose start;
  start.position = Vec3(0, 0, 0.1);
  MouseInstrumentDevice device(start);
  DeviceSample s;
  ASSERT_TRUE(device.sample(0.001, s));
  EXPECT_EQ(s.pose.position, start.position);
  EXPECT_FALSE(s.end);
  Pose moved = start;
  moved.position.x() = 0.01;
  device.set_pose(moved);
  device.request_end();
  ASSERT_TRUE(device.sample(0.002, s));
  EXPECT_EQ(s.pose.position, moved.position);
  EXPECT_TRUE(s.end);
}

}  // namespace
}  // namespace acdr
