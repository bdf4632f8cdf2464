// The haptic bridge protocol: every message round-trips, the byte layout is the documented
// one (docs/haptic-bridge.md), and malformed datagrams are rejected with a reason.
#include "engine/devices/udp_bridge_protocol.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace acdr::bridge {
namespace {

Message pose_message() {
  Message m;
  m.type = MessageType::kPose;
  m.sequence = 0x01020304u;
  m.session = 0xA1B2C3D4u;
  m.timestamp_s = 12.5;
  m.pose.position = Vec3(0.01, -0.02, 0.11);
  m.pose.orientation = Quat(Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()));
  m.buttons = 0b101;
  return m;
}

std::vector<std::uint8_t> encoded(const Message& m) {
  std::vector<std::uint8_t> bytes(kMaxMessageSize + 8, 0xEE);
  const std::size_t n = encode(m, bytes);
  bytes.resize(n);
  return bytes;
}

double f64_at(const std::vector<std::uint8_t>& b, std::size_t offset) {
  std::uint64_t bits = 0;
  for (int i = 0; i < 8; ++i) bits |= static_cast<std::uint64_t>(b[offset + i]) << (8 * i);
  double v;
  std::memcpy(&v, &bits, 8);
  return v;
}

TEST(BridgeProtocol, PoseRoundTripsWithTheDocumentedLayout) {
  const Message m = pose_message();
  const auto bytes = encoded(m);
  ASSERT_EQ(bytes.size(), kPoseSize);
  ASSERT_EQ(kPoseSize, 88u);
  // Header: "ACDH", version 2 (LE u16), type, flags, sequence (LE u32), session (LE u32),
  // timestamp.
  EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + 4), "ACDH");
  EXPECT_EQ(bytes[4], 2);
  EXPECT_EQ(bytes[5], 0);
  EXPECT_EQ(bytes[6], 1);
  EXPECT_EQ(bytes[8], 0x04);
  EXPECT_EQ(bytes[11], 0x01);
  EXPECT_EQ(bytes[12], 0xD4);
  EXPECT_EQ(bytes[15], 0xA1);
  EXPECT_EQ(f64_at(bytes, 16), 12.5);
  // Body: position x, y, z at 24, 32, 40; quaternion w, x, y, z at 48..; buttons at 80.
  EXPECT_EQ(f64_at(bytes, 24), 0.01);
  EXPECT_EQ(f64_at(bytes, 40), 0.11);
  EXPECT_EQ(f64_at(bytes, 48), m.pose.orientation.w());
  EXPECT_EQ(bytes[80], 0b101);

  Message back;
  ASSERT_EQ(decode(bytes, back), DecodeError::kNone);
  EXPECT_EQ(back.type, MessageType::kPose);
  EXPECT_EQ(back.sequence, m.sequence);
  EXPECT_EQ(back.session, m.session);
  EXPECT_EQ(back.timestamp_s, m.timestamp_s);
  EXPECT_EQ(back.pose.position, m.pose.position);
  EXPECT_EQ(back.pose.orientation.coeffs(), m.pose.orientation.coeffs());
  EXPECT_EQ(back.buttons, m.buttons);
}

TEST(BridgeProtocol, ForceAndEndMessagesRoundTrip) {
  Message f;
  f.type = MessageType::kForce;
  f.sequence = 7;
  f.force_N = Vec3(0.5, -1.25, 3.3);
  f.ack_sequence = 99;
  f.status = kStatusRunning | kStatusForceZeroed;
  const auto fb = encoded(f);
  ASSERT_EQ(fb.size(), kForceSize);
  Message back;
  ASSERT_EQ(decode(fb, back), DecodeError::kNone);
  EXPECT_EQ(back.type, MessageType::kForce);
  EXPECT_EQ(back.force_N, f.force_N);
  EXPECT_EQ(back.ack_sequence, 99u);
  EXPECT_EQ(back.status, f.status);

  for (MessageType t : {MessageType::kEndOfAttempt, MessageType::kAttemptOver}) {
    Message e;
    e.type = t;
    e.sequence = 3;
    e.reason = EndReason::kTimeLimit;
    const auto eb = encoded(e);
    ASSERT_EQ(eb.size(), kEndSize);
    Message eback;
    ASSERT_EQ(decode(eb, eback), DecodeError::kNone);
    EXPECT_EQ(eback.type, t);
    EXPECT_EQ(eback.reason, EndReason::kTimeLimit);
  }
}

// The session handshake: hello carries the bridge's nonce; welcome the session number in its
// header and the nonce back, both 32 bytes (type 5 and 6).
TEST(BridgeProtocol, HelloAndWelcomeRoundTrip) {
  for (MessageType t : {MessageType::kHello, MessageType::kWelcome}) {
    Message h;
    h.type = t;
    h.sequence = 1;
    h.session = t == MessageType::kWelcome ? 0x01020304u : 0u;
    h.nonce = 0xCAFEF00Du;
    const auto hb = encoded(h);
    ASSERT_EQ(hb.size(), kHelloSize);
    EXPECT_EQ(hb[6], static_cast<std::uint8_t>(t));
    EXPECT_EQ(hb[24], 0x0D);
    EXPECT_EQ(hb[27], 0xCA);
    Message back;
    ASSERT_EQ(decode(hb, back), DecodeError::kNone);
    EXPECT_EQ(back.type, t);
    EXPECT_EQ(back.nonce, h.nonce);
    EXPECT_EQ(back.session, h.session);
  }
}

TEST(BridgeProtocol, EncodeRefusesATooSmallBuffer) {
  std::vector<std::uint8_t> small(kPoseSize - 1);
  EXPECT_EQ(encode(pose_message(), small), 0u);
}

TEST(BridgeProtocol, RejectsMalformedDatagramsSayingWhy) {
  const auto good = encoded(pose_message());
  Message out;
  std::string why;

  EXPECT_EQ(decode(std::span<const std::uint8_t>(good.data(), 10), out, &why),
            DecodeError::kTooShort);
  EXPECT_NE(why.find("10 bytes"), std::string::npos) << why;

  auto bad_magic = good;
  bad_magic[0] = 'X';
  EXPECT_EQ(decode(bad_magic, out, &why), DecodeError::kBadMagic);

  auto bad_version = good;
  bad_version[4] = 1;  // version 1 had no session: refused, not misread
  EXPECT_EQ(decode(bad_version, out, &why), DecodeError::kBadVersion);
  EXPECT_NE(why.find("version 1"), std::string::npos) << why;

  auto bad_type = good;
  bad_type[6] = 9;
  EXPECT_EQ(decode(bad_type, out, &why), DecodeError::kUnknownType);

  auto truncated = good;
  truncated.pop_back();
  EXPECT_EQ(decode(truncated, out, &why), DecodeError::kBadSize);
  EXPECT_NE(why.find("88 bytes, got 87"), std::string::npos) << why;

  auto extended = good;
  extended.push_back(0);
  EXPECT_EQ(decode(extended, out, &why), DecodeError::kBadSize);

  // A pose header on a force-sized body: the size must match the type.
  auto mismatched = good;
  mismatched.resize(kForceSize);
  EXPECT_EQ(decode(mismatched, out, &why), DecodeError::kBadSize);
}

TEST(BridgeProtocol, NonFiniteValuesDecodeSoTheGuardCanRecordThem) {
  Message m = pose_message();
  m.pose.position.y() = std::numeric_limits<double>::quiet_NaN();
  Message back;
  ASSERT_EQ(decode(encoded(m), back), DecodeError::kNone);
  EXPECT_TRUE(std::isnan(back.pose.position.y()));
}

TEST(BridgeProtocol, RandomBytesNeverDecodeUnlessTheyFormAMessage) {
  std::mt19937 rng(1234);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_int_distribution<int> length(0, 120);
  int accepted = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    std::vector<std::uint8_t> bytes(length(rng));
    for (auto& b : bytes) b = static_cast<std::uint8_t>(byte(rng));
    // Half the trials start with a valid header prefix to reach the later checks.
    if (trial % 2 == 0 && bytes.size() >= 8) {
      std::memcpy(bytes.data(), "ACDH\x02\x00", 6);
      bytes[6] = static_cast<std::uint8_t>(1 + trial % 6);
    }
    Message out;
    if (decode(bytes, out) == DecodeError::kNone) {
      ++accepted;
      EXPECT_EQ(bytes.size(), message_size(out.type));
    }
  }
  // Only datagrams of exactly the right size for their type can pass.
  EXPECT_LT(accepted, 2000);
}

}  // namespace
}  // namespace acdr::bridge
