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
  EXPECT_NEAR(apply_mouse_input(start, in, looking_north()).position.z(), 0.006, 1e-12);
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

TEST(MouseInstrument, WheelAndRightDragSetTheDepthAndCtrlDragTurns) {
  const Pose start;
  MouseKeyInput in;
  in.wheel_notches = 4;  // forward: in, 0.5 mm a notch
  EXPECT_NEAR(apply_mouse_input(start, in, looking_north()).position.z(), -2e-3, 1e-12);
  in = {};
  in.depth_drag_px = -30;  // up the screen: out, 0.1 mm a pixel
  EXPECT_NEAR(apply_mouse_input(start, in, looking_north()).position.z(), 3e-3, 1e-12);
  EXPECT_NEAR(apply_mouse_input(start, in, looking_north()).position.x(), 0.0, 1e-12);
  in = {};
  in.turn_dy_px = 40;  // Ctrl + drag down: tilt about the view's right axis (x)
  const Pose tilted = apply_mouse_input(start, in, looking_north());
  EXPECT_NEAR(start.orientation.angularDistance(tilted.orientation), 0.2, 1e-9);
  EXPECT_EQ(tilted.position, start.position);
  const Vec3 axis = tilted.orientation * Vec3::UnitZ();
  EXPECT_NEAR(axis.x(), 0.0, 1e-9);
}

TEST(MouseInstrument, OneFrameMovesTheGoalAtMostItsCapAndHoldFreezes) {
  const Pose start;
  MouseKeyInput in;
  in.drag_dx_px = 5000;
  EXPECT_NEAR(apply_mouse_input(start, in, looking_north()).position.norm(), 0.03, 1e-12);
  in.hold = true;
  EXPECT_EQ(apply_mouse_input(start, in, looking_north()).position, start.position);
}

TEST(MouseInstrument, TheGripKeyClosesTheJawsInTheSamples) {
  MouseInstrumentDevice device{Pose{}};
  DeviceSample s;
  ASSERT_TRUE(device.sample(0.001, s));
  EXPECT_EQ(s.grip, 0.0);
  device.set_grip(1.0);
  ASSERT_TRUE(device.sample(0.002, s));
  EXPECT_EQ(s.grip, 1.0);
  device.set_grip(0.0);
  ASSERT_TRUE(device.sample(0.003, s));
  EXPECT_EQ(s.grip, 0.0);
}

TEST(MouseInstrument, DeviceFollowsTheGoalAtItsSpeedAndGivesTheEnd) {
  Pose start;
  start.position = Vec3(0, 0, 0.1);
  MouseInstrumentDevice device(start);  // 20 mm/s, 2 rad/s
  DeviceSample s;
  ASSERT_TRUE(device.sample(0.001, s));
  EXPECT_EQ(s.pose.position, start.position);
  EXPECT_FALSE(s.end);
  Pose goal = start;
  goal.position.x() = 0.01;  // 10 mm away: 0.5 s at 20 mm/s
  goal.orientation = Quat(Eigen::AngleAxisd(0.1, Vec3::UnitX()));
  device.set_pose(goal);
  EXPECT_EQ(device.pose().position, goal.position);  // the goal, for the window
  ASSERT_TRUE(device.sample(0.011, s));              // 10 ms later: 0.2 mm and 0.02 rad on
  EXPECT_NEAR(s.pose.position.x(), 0.2e-3, 1e-12);
  EXPECT_NEAR(start.orientation.angularDistance(s.pose.orientation), 0.02, 1e-9);
  EXPECT_EQ(device.current().position, s.pose.position);
  double t = 0.011;
  for (int i = 0; i < 600; ++i) {  // then it arrives, and no sample moved more than 1 ms allows
    const Vec3 before = s.pose.position;
    t += 0.001;
    ASSERT_TRUE(device.sample(t, s));
    ASSERT_LE((s.pose.position - before).norm(), 0.02e-3 + 1e-12);
  }
  EXPECT_NEAR((s.pose.position - goal.position).norm(), 0.0, 1e-12);
  EXPECT_NEAR(s.pose.orientation.angularDistance(goal.orientation), 0.0, 1e-9);
  device.request_end();
  ASSERT_TRUE(device.sample(t + 0.001, s));
  EXPECT_TRUE(s.end);
}

// Given the attempt's clock, the grip counts its speed in simulated seconds: in slow motion
// (here a quarter of real time) it covers a quarter of the distance per second of the
// device loop, the same distance per simulated second as in real time.
TEST(MouseInstrument, SpeedsCountTheClockItIsGiven) {
  Pose start;
  start.position = Vec3(0, 0, 0.1);
  MouseInstrumentDevice device(start);  // 20 mm/s
  double simulated_s = 0.0;
  device.count_time_by([&] { return simulated_s; });
  Pose goal = start;
  goal.position.x() = 0.01;
  device.set_pose(goal);
  DeviceSample s;
  ASSERT_TRUE(device.sample(0.0, s));
  for (int tick = 1; tick <= 100; ++tick) {  // 100 ms of the device loop, 25 ms simulated
    simulated_s = 0.25e-3 * tick;
    ASSERT_TRUE(device.sample(1e-3 * tick, s));
  }
  EXPECT_NEAR(s.pose.position.x(), 0.5e-3, 1e-9);  // 25 ms at 20 mm/s
  EXPECT_DOUBLE_EQ(s.t_s, 0.1);                    // the sample keeps the loop's own time
  // Without the clock the loop's time counts again, from the next sample on.
  device.count_time_by({});
  ASSERT_TRUE(device.sample(0.2, s));
  ASSERT_TRUE(device.sample(0.21, s));
  EXPECT_NEAR(s.pose.position.x(), 0.7e-3, 1e-9);
}

}  // namespace
}  // namespace acdr
