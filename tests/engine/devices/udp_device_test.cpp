// The UDP bridge device against a hand-driven fake bridge on loopback: poses in, forces out,
// lost and late packets counted, malformed datagrams rejected, silence -> stale (force off),
// long silence -> disconnected, end-of-attempt and attempt-over.
#include "engine/devices/udp_device.hpp"

#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <thread>

namespace acdr {
namespace {

using namespace std::chrono_literals;

class FakeBridge {
 public:
  /// A bridge that has not said hello (an intruder, or before handshake()).
  explicit FakeBridge(int simulator_port) : to_(make_endpoint("127.0.0.1", simulator_port)) {
    std::string error;
    socket_ = UdpSocket::bind("127.0.0.1", 0, &error);
    EXPECT_TRUE(socket_) << error;
  }
  /// A bridge welcomed into `d`'s session (the handshake done).
  explicit FakeBridge(UdpDevice& d) : FakeBridge(d.port()) { EXPECT_TRUE(handshake(d)); }

  /// Says hello (nonce `nonce`) and lets `d` answer; true when welcomed with our nonce.
  bool handshake(UdpDevice& d, std::uint32_t nonce = 0x5EED1234u) {
    bridge::Message hello;
    hello.type = bridge::MessageType::kHello;
    hello.nonce = nonce;
    send(hello);
    const auto give_up = std::chrono::steady_clock::now() + 1s;
    while (std::chrono::steady_clock::now() < give_up) {
      d.wait_for_connection(0.002);  // reads the hello, answers it
      bridge::Message m;
      if (receive(m, 0.01) && m.type == bridge::MessageType::kWelcome && m.nonce == nonce) {
        session = m.session;
        return true;
      }
    }
    return false;
  }
  void pose(std::uint32_t sequence, const Vec3& position) {
    bridge::Message m;
    m.type = bridge::MessageType::kPose;
    m.sequence = sequence;
    m.pose.position = position;
    send(m);
  }
  void end() {
    bridge::Message m;
    m.type = bridge::MessageType::kEndOfAttempt;
    m.reason = bridge::EndReason::kUserFinished;
    send(m);
  }
  /// Sends `m` in our session (0 before the handshake).
  void send(bridge::Message m) {
    m.session = session;
    std::array<std::uint8_t, bridge::kMaxMessageSize> b;
    const std::size_t n = bridge::encode(m, b);
    raw(std::span<const std::uint8_t>(b.data(), n));
  }
  void raw(std::span<const std::uint8_t> bytes) { ASSERT_TRUE(socket_->send_to(to_, bytes)); }
  // The next message from the simulator, waiting up to `wait_s`.
  bool receive(bridge::Message& m, double wait_s = 1.0) {
    std::array<std::uint8_t, 256> b;
    if (!socket_->wait_readable(wait_s)) return false;
    const long n = socket_->receive(b, nullptr);
    return n > 0 && bridge::decode(std::span<const std::uint8_t>(b.data(), n), m) ==
                        bridge::DecodeError::kNone;
  }

  std::uint32_t session = 0;  ///< from the simulator's welcome

 private:
  UdpEndpoint to_;
  std::unique_ptr<UdpSocket> socket_;
};

std::unique_ptr<UdpDevice> open_device(double silence = 0.05, double disconnect = 5.0) {
  UdpDeviceOptions options;
  options.silence_limit_s = silence;
  options.disconnect_timeout_s = disconnect;
  std::string error;
  auto d = UdpDevice::open(options, &error);
  EXPECT_TRUE(d) << error;
  return d;
}

// Samples until `done` holds or 1 s passes (datagrams on loopback arrive within microseconds,
// but the receiving thread may not run at once on a busy machine).
template <class Done>
DeviceSample sample_until(UdpDevice& d, Done done) {
  DeviceSample s;
  const auto give_up = std::chrono::steady_clock::now() + 1s;
  while (std::chrono::steady_clock::now() < give_up) {
    d.sample(0.0, s);
    if (done(s)) break;
    std::this_thread::sleep_for(1ms);
  }
  return s;
}

TEST(UdpDevice, BindsAndRefusesAPortInUse) {
  auto a = open_device();
  UdpDeviceOptions same;
  same.port = a->port();
  std::string error;
  EXPECT_FALSE(UdpDevice::open(same, &error));
  EXPECT_NE(error.find("cannot bind"), std::string::npos) << error;
}

TEST(UdpDevice, WaitsForTheFirstPoseThenFollowsIt) {
  auto d = open_device();
  EXPECT_FALSE(d->wait_for_connection(0.05));  // nobody there
  DeviceSample s;
  EXPECT_FALSE(d->sample(0.0, s));  // nothing to follow yet: the start pose stays
  FakeBridge bridge(*d);
  bridge.pose(0, Vec3(0.01, 0.02, 0.03));
  ASSERT_TRUE(d->wait_for_connection(1.0));
  s = sample_until(*d, [](const DeviceSample& x) { return x.pose.position.x() > 0; });
  EXPECT_EQ(s.pose.position, Vec3(0.01, 0.02, 0.03));
  EXPECT_FALSE(s.stale);
  EXPECT_TRUE(d->stats().connected);
}

TEST(UdpDevice, CountsLostAndDropsLatePackets) {
  auto d = open_device();
  FakeBridge bridge(*d);
  bridge.pose(10, Vec3(0.001, 0, 0));
  ASSERT_TRUE(d->wait_for_connection(1.0));
  bridge.pose(11, Vec3(0.002, 0, 0));
  bridge.pose(15, Vec3(0.003, 0, 0));  // 12, 13, 14 lost
  bridge.pose(13, Vec3(0.999, 0, 0));  // arrives late: dropped, never followed
  DeviceSample s = sample_until(*d, [&](const DeviceSample&) {
    return d->stats().packets_received >= 4;
  });
  EXPECT_EQ(s.pose.position.x(), 0.003);
  const UdpDeviceStats st = d->stats();
  EXPECT_EQ(st.packets_lost, 3);
  EXPECT_EQ(st.packets_late, 1);
}

TEST(UdpDevice, RejectsMalformedDatagrams) {
  auto d = open_device();
  FakeBridge bridge(*d);
  bridge.pose(0, Vec3(0.001, 0, 0));
  ASSERT_TRUE(d->wait_for_connection(1.0));
  const std::array<std::uint8_t, 5> garbage = {1, 2, 3, 4, 5};
  bridge.raw(garbage);
  bridge::Message wrong_way;  // a force sent to the simulator
  wrong_way.type = bridge::MessageType::kForce;
  bridge.send(wrong_way);
  std::array<std::uint8_t, 200> oversized{};
  bridge.raw(oversized);
  sample_until(*d, [&](const DeviceSample&) { return d->stats().packets_malformed >= 3; });
  const UdpDeviceStats st = d->stats();
  EXPECT_EQ(st.packets_malformed, 3);
  EXPECT_FALSE(st.last_malformed.empty());
  EXPECT_EQ(st.packets_received, 1);
}

TEST(UdpDevice, AnswersWithForceAndAcknowledgesTheNewestPose) {
  auto d = open_device();
  FakeBridge bridge(*d);
  bridge.pose(41, Vec3::Zero());
  ASSERT_TRUE(d->wait_for_connection(1.0));
  DeviceSample s;
  d->sample(0.001, s);
  d->render_force(Vec3(0.5, 0, -1.0));
  bridge::Message m;
  ASSERT_TRUE(bridge.receive(m));
  EXPECT_EQ(m.type, bridge::MessageType::kForce);
  EXPECT_EQ(m.force_N, Vec3(0.5, 0, -1.0));
  EXPECT_EQ(m.ack_sequence, 41u);
  EXPECT_TRUE(m.status & bridge::kStatusRunning);
  // A non-finite force never leaves.
  d->render_force(Vec3(NAN, 0, 0));
  ASSERT_TRUE(bridge.receive(m));
  EXPECT_EQ(m.force_N, Vec3::Zero());
  EXPECT_NEAR(d->stats().max_force_sent_N, std::sqrt(1.25), 1e-12);
}

TEST(UdpDevice, SilenceMakesTheSampleStaleThenDisconnected) {
  auto d = open_device(/*silence=*/0.02, /*disconnect=*/0.15);
  FakeBridge bridge(*d);
  bridge.pose(0, Vec3::Zero());
  ASSERT_TRUE(d->wait_for_connection(1.0));
  DeviceSample s;
  d->sample(0.0, s);
  EXPECT_FALSE(s.stale);
  std::this_thread::sleep_for(40ms);
  d->sample(0.0, s);
  EXPECT_TRUE(s.stale);
  EXPECT_FALSE(s.disconnected);
  EXPECT_GE(s.silence_s, 0.02);
  // Fresh data clears it.
  bridge.pose(1, Vec3::Zero());
  s = sample_until(*d, [](const DeviceSample& x) { return !x.stale; });
  EXPECT_FALSE(s.stale);
  // A long silence disconnects.
  std::this_thread::sleep_for(200ms);
  d->sample(0.0, s);
  EXPECT_TRUE(s.stale);
  EXPECT_TRUE(s.disconnected);
  const UdpDeviceStats st = d->stats();
  EXPECT_TRUE(st.disconnected);
  EXPECT_EQ(st.silences, 2);
  EXPECT_GE(st.longest_silence_s, 0.15);
}

TEST(UdpDevice, EndOfAttemptEndsAndFinishSaysAttemptOver) {
  auto d = open_device();
  FakeBridge bridge(*d);
  bridge.pose(0, Vec3::Zero());
  ASSERT_TRUE(d->wait_for_connection(1.0));
  bridge.end();
  const DeviceSample s = sample_until(*d, [](const DeviceSample& x) { return x.end; });
  EXPECT_TRUE(s.end);
  d->finish("input ended");
  bridge::Message m;
  ASSERT_TRUE(bridge.receive(m));
  EXPECT_EQ(m.type, bridge::MessageType::kAttemptOver);
  EXPECT_EQ(m.reason, bridge::EndReason::kInputEnded);
}

// The session belongs to the bridge that opened it. A second local program that sends poses
// with higher sequence numbers (without a session, or even with the right session number from
// its own port), or says hello itself, is counted and ignored: the pose followed stays the
// bridge's, no force or welcome goes to the intruder, and the bridge keeps its forces.
TEST(UdpDevice, AnIntruderWithHigherSequenceNumbersChangesNothingAndGetsNoForce) {
  auto d = open_device();
  FakeBridge bridge(*d);
  bridge.pose(10, Vec3(0.001, 0, 0));
  ASSERT_TRUE(d->wait_for_connection(1.0));
  FakeBridge intruder(d->port());
  intruder.pose(1000, Vec3(0.5, 0, 0));   // no session at all
  intruder.session = bridge.session;      // the right number, but not the bridge's port
  intruder.pose(2000, Vec3(0.6, 0, 0));
  intruder.end();
  EXPECT_FALSE(intruder.handshake(*d));   // says hello: never welcomed
  sample_until(*d, [&](const DeviceSample&) { return d->stats().packets_foreign >= 4; });
  DeviceSample s;
  ASSERT_TRUE(d->sample(0.002, s));
  EXPECT_EQ(s.pose.position, Vec3(0.001, 0, 0));
  EXPECT_FALSE(s.end);
  for (int i = 0; i < 5; ++i) d->render_force(Vec3(0.1, 0, 0));
  bridge::Message m;
  EXPECT_FALSE(intruder.receive(m, 0.1)) << "the intruder got message type "
                                         << static_cast<int>(m.type);
  int forces = 0;
  while (bridge.receive(m, 0.1)) forces += m.type == bridge::MessageType::kForce;
  EXPECT_EQ(forces, 5);
  EXPECT_EQ(m.session, bridge.session);
  // The bridge's own next pose is still followed: the sequence is its own, not the intruder's.
  bridge.pose(11, Vec3(0.002, 0, 0));
  s = sample_until(*d, [](const DeviceSample& x) { return x.pose.position.x() == 0.002; });
  EXPECT_EQ(s.pose.position, Vec3(0.002, 0, 0));
  const UdpDeviceStats st = d->stats();
  EXPECT_EQ(st.packets_received, 2);
  EXPECT_EQ(st.packets_lost, 0);
  EXPECT_EQ(st.packets_late, 0);
  EXPECT_GE(st.packets_foreign, 4);
  EXPECT_FALSE(st.end_of_attempt);
  EXPECT_FALSE(st.last_foreign.empty());
  EXPECT_NE(st.last_foreign, st.bridge);
}

// A welcome may be lost: the same bridge's hello (same port, same nonce) is answered again,
// with the same session.
TEST(UdpDevice, TheSameBridgesHelloIsWelcomedAgain) {
  auto d = open_device();
  FakeBridge bridge(*d);
  const std::uint32_t first = bridge.session;
  EXPECT_NE(first, 0u);
  ASSERT_TRUE(bridge.handshake(*d));
  EXPECT_EQ(bridge.session, first);
  EXPECT_FALSE(bridge.handshake(*d, 0x0BADu));  // another nonce: another bridge's hello
  EXPECT_EQ(d->stats().packets_foreign, 1);
}

}  // namespace
}  // namespace acdr
