// The virtual device against the UDP device on loopback, with a stand-in for the simulator
// (a haptic loop that samples the device and answers with a force): the trajectory arrives
// in order, forces come back, faults are injected as asked, and the ends are exchanged.
#include "engine/devices/virtual_bridge.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <thread>

#include "engine/devices/haptic_loop.hpp"
#include "engine/devices/udp_device.hpp"

namespace acdr {
namespace {

// 0.3 s along x from 0 to 3 mm.
Trajectory line() {
  std::vector<TrajectorySample> s(2);
  s[0].t_s = 0.0;
  s[1].t_s = 0.3;
  s[1].pose.position = Vec3(0.003, 0, 0);
  return Trajectory(std::move(s));
}

struct LoopbackResult {
  VirtualBridgeResult bridge;
  UdpDeviceStats device;
  std::vector<DeviceSample> samples;
};

// Runs the virtual device against a UdpDevice stepped at 1 kHz until the device says end.
LoopbackResult run_loopback(VirtualBridgeOptions options) {
  LoopbackResult r;
  std::string error;
  auto device = UdpDevice::open(UdpDeviceOptions{}, &error);
  EXPECT_TRUE(device) << error;
  options.port = device->port();
  std::thread bridge_thread([&] { r.bridge = VirtualBridge(line(), options).run(); });
  EXPECT_TRUE(device->wait_for_connection(5.0));
  HapticLoop loop;
  r.samples.reserve(2000);
  loop.start([&] {
    DeviceSample s;
    if (!device->sample(0.0, s)) return true;
    r.samples.push_back(s);
    // Answer with a force proportional to x (N per m), like a spring.
    device->render_force(Vec3(-1000.0 * (std::isfinite(s.pose.position.x()) ? s.pose.position.x()
                                                                              : 0.0),
                              0, 0));
    return !s.end && r.samples.size() < 2000;
  });
  loop.join();
  device->finish("input ended");
  bridge_thread.join();
  r.device = device->stats();
  return r;
}

TEST(VirtualBridge, PlaysTheTrajectoryAndExchangesForcesAndEnds) {
  const LoopbackResult r = run_loopback({});
  ASSERT_TRUE(r.bridge.error.empty()) << r.bridge.error;
  EXPECT_TRUE(r.bridge.connected);
  EXPECT_TRUE(r.bridge.sent_end);
  EXPECT_TRUE(r.bridge.attempt_over);
  EXPECT_EQ(r.bridge.attempt_over_reason, bridge::EndReason::kInputEnded);
  ASSERT_FALSE(r.samples.empty());
  EXPECT_TRUE(r.samples.back().end);
  // Positions never go backwards and reach the end of the line.
  double last_x = -1;
  for (const DeviceSample& s : r.samples) {
    EXPECT_GE(s.pose.position.x(), last_x - 1e-12);
    last_x = s.pose.position.x();
  }
  EXPECT_NEAR(last_x, 0.003, 1e-9);
  // About 300 poses at 1 kHz plus the connect phase; forces came back for them.
  EXPECT_GE(r.bridge.poses_sent, 290);
  EXPECT_EQ(r.device.packets_lost, 0);
  EXPECT_GT(r.bridge.forces_received, 100);
  EXPECT_NEAR(r.bridge.max_force_N, 3.0, 0.2);  // 1000 N/m x 3 mm
  EXPECT_NEAR(r.bridge.loop.rate_hz, 1000.0, 100.0);
  EXPECT_FALSE(r.bridge.peer_lost);
  EXPECT_EQ(r.bridge.packets_foreign, 0);
  EXPECT_EQ(r.device.packets_foreign, 0);
}

TEST(VirtualBridge, DroppedPacketsAreCountedAsLostByTheDevice) {
  VirtualBridgeOptions options;
  options.drop_every = 10;
  const LoopbackResult r = run_loopback(options);
  EXPECT_GT(r.bridge.poses_dropped, 25);
  EXPECT_EQ(r.device.packets_lost, r.bridge.poses_dropped);
}

TEST(VirtualBridge, InjectedNaNAndSilenceReachTheDevice) {
  VirtualBridgeOptions options;
  options.nan_at_s = 0.1;
  // A few NaN poses in a row: the device samples the newest pose, and on a busy machine a
  // single bad packet can be overtaken by the next before the simulator looks.
  options.nan_for_s = 0.005;
  options.silence_at_s = 0.15;
  options.silence_for_s = 0.1;  // twice the device's 50 ms silence limit
  const LoopbackResult r = run_loopback(options);
  int nan_samples = 0, stale_samples = 0;
  for (const DeviceSample& s : r.samples) {
    nan_samples += !s.pose.position.allFinite();
    stale_samples += s.stale;
  }
  EXPECT_GE(nan_samples, 1);
  EXPECT_GT(stale_samples, 10);
  EXPECT_EQ(r.device.silences, 1);
  EXPECT_GE(r.device.longest_silence_s, 0.09);
}

// A simulator that dies mid-attempt (no attempt-over, no more forces) is noticed after the
// peer timeout: the bridge stops playing and reports the peer lost, not connected.
TEST(VirtualBridge, NoticesASimulatorThatStoppedAnswering) {
  std::string error;
  auto device = UdpDevice::open(UdpDeviceOptions{}, &error);
  ASSERT_TRUE(device) << error;
  VirtualBridgeOptions options;
  options.port = device->port();
  options.peer_timeout_s = 0.1;
  VirtualBridgeResult r;
  std::thread bridge_thread([&] {
    // 3 s to play: far longer than the simulator lives.
    std::vector<TrajectorySample> s(2);
    s[1].t_s = 3.0;
    r = VirtualBridge(Trajectory(std::move(s)), options).run();
  });
  ASSERT_TRUE(device->wait_for_connection(5.0));
  for (int tick = 0; tick < 50; ++tick) {  // 50 ms of a live simulator, then silence
    DeviceSample sample;
    device->sample(0.0, sample);
    device->render_force(Vec3::Zero());
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  bridge_thread.join();
  ASSERT_TRUE(r.error.empty()) << r.error;
  EXPECT_TRUE(r.peer_lost);
  EXPECT_FALSE(r.connected);
  EXPECT_FALSE(r.sent_end);
  EXPECT_FALSE(r.attempt_over);
  EXPECT_GE(r.last_force_at_s, 0.0);
  EXPECT_LT(r.played_s, 2.0);
  EXPECT_NE(r.session, 0u);
  EXPECT_GT(r.forces_received, 0);
}

TEST(VirtualBridge, ReportsWhenNoSimulatorAnswers) {
  VirtualBridgeOptions options;
  options.port = 9;  // discard: nobody answers
  options.connect_timeout_s = 0.1;
  const VirtualBridgeResult r = VirtualBridge(line(), options).run();
  EXPECT_FALSE(r.connected);
  EXPECT_NE(r.error.find("no answer"), std::string::npos) << r.error;
}

}  // namespace
}  // namespace acdr
