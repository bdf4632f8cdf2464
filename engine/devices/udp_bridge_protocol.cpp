// Haptic bridge protocol: byte-exact little-endian encoding, independent of the host's order.
#include "engine/devices/udp_bridge_protocol.hpp"

#include <cstring>

namespace acdr::bridge {
namespace {

// Little-endian writer/reader over a byte span; the caller has checked the sizes.
struct Writer {
  std::uint8_t* p;
  void u8(std::uint8_t v) { *p++ = v; }
  void u16(std::uint16_t v) {
    for (int i = 0; i < 2; ++i) *p++ = static_cast<std::uint8_t>(v >> (8 * i));
  }
  void u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) *p++ = static_cast<std::uint8_t>(v >> (8 * i));
  }
  void u64(std::uint64_t v) {
    for (int i = 0; i < 8; ++i) *p++ = static_cast<std::uint8_t>(v >> (8 * i));
  }
  void f64(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, 8);
    u64(bits);
  }
};

struct Reader {
  const std::uint8_t* p;
  std::uint8_t u8() { return *p++; }
  std::uint16_t u16() {
    std::uint16_t v = 0;
    for (int i = 0; i < 2; ++i) v |= static_cast<std::uint16_t>(*p++) << (8 * i);
    return v;
  }
  std::uint32_t u32() {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(*p++) << (8 * i);
    return v;
  }
  std::uint64_t u64() {
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(*p++) << (8 * i);
    return v;
  }
  double f64() {
    const std::uint64_t bits = u64();
    double v;
    std::memcpy(&v, &bits, 8);
    return v;
  }
};

bool known_type(std::uint8_t t) { return t >= 1 && t <= 6; }

}  // namespace

std::size_t message_size(MessageType type) {
  switch (type) {
    case MessageType::kPose: return kPoseSize;
    case MessageType::kForce: return kForceSize;
    case MessageType::kEndOfAttempt:
    case MessageType::kAttemptOver: return kEndSize;
    case MessageType::kHello:
    case MessageType::kWelcome: return kHelloSize;
  }
  return 0;
}

std::size_t encode(const Message& m, std::span<std::uint8_t> out) {
  const std::size_t size = message_size(m.type);
  if (size == 0 || out.size() < size) return 0;
  Writer w{out.data()};
  // Header: magic, version, type, flags (0), sequence, session, timestamp.
  for (std::uint8_t b : kMagic) w.u8(b);
  w.u16(kVersion);
  w.u8(static_cast<std::uint8_t>(m.type));
  w.u8(0);
  w.u32(m.sequence);
  w.u32(m.session);
  w.f64(m.timestamp_s);
  switch (m.type) {
    case MessageType::kPose:
      for (int i = 0; i < 3; ++i) w.f64(m.pose.position[i]);
      w.f64(m.pose.orientation.w());
      w.f64(m.pose.orientation.x());
      w.f64(m.pose.orientation.y());
      w.f64(m.pose.orientation.z());
      w.u32(m.buttons);
      w.u32(0);
      break;
    case MessageType::kForce:
      for (int i = 0; i < 3; ++i) w.f64(m.force_N[i]);
      w.u32(m.ack_sequence);
      w.u32(m.status);
      break;
    case MessageType::kEndOfAttempt:
    case MessageType::kAttemptOver:
      w.u32(static_cast<std::uint32_t>(m.reason));
      w.u32(0);
      break;
    case MessageType::kHello:
    case MessageType::kWelcome:
      w.u32(m.nonce);
      w.u32(0);
      break;
  }
  return size;
}

const char* decode_error_name(DecodeError e) {
  switch (e) {
    case DecodeError::kNone: return "ok";
    case DecodeError::kTooShort: return "too short";
    case DecodeError::kBadMagic: return "bad magic";
    case DecodeError::kBadVersion: return "unsupported version";
    case DecodeError::kUnknownType: return "unknown message type";
    case DecodeError::kBadSize: return "wrong size for its type";
  }
  return "?";
}

DecodeError decode(std::span<const std::uint8_t> bytes, Message& out, std::string* detail) {
  auto fail = [&](DecodeError e, const std::string& what) {
    if (detail) *detail = std::string(decode_error_name(e)) + ": " + what;
    return e;
  };
  if (bytes.size() < kHeaderSize)
    return fail(DecodeError::kTooShort, "got " + std::to_string(bytes.size()) +
                                            " bytes, expected at least " +
                                            std::to_string(kHeaderSize));
  Reader r{bytes.data()};
  for (std::uint8_t b : kMagic) {
    if (r.u8() != b) return fail(DecodeError::kBadMagic, "expected the bytes 'ACDH'");
  }
  const std::uint16_t version = r.u16();
  if (version != kVersion)
    return fail(DecodeError::kBadVersion, "got version " + std::to_string(version) +
                                              ", expected " + std::to_string(kVersion));
  const std::uint8_t type = r.u8();
  if (!known_type(type))
    return fail(DecodeError::kUnknownType,
                "got type " + std::to_string(type) +
                    ", expected 1 (pose), 2 (force), 3 (end of attempt), 4 (attempt over), "
                    "5 (hello) or 6 (welcome)");
  out.type = static_cast<MessageType>(type);
  const std::size_t expected = message_size(out.type);
  if (bytes.size() != expected)
    return fail(DecodeError::kBadSize, "type " + std::to_string(type) + " has " +
                                           std::to_string(expected) + " bytes, got " +
                                           std::to_string(bytes.size()));
  r.u8();  // flags: reserved
  out.sequence = r.u32();
  out.session = r.u32();
  out.timestamp_s = r.f64();
  switch (out.type) {
    case MessageType::kPose: {
      for (int i = 0; i < 3; ++i) out.pose.position[i] = r.f64();
      const double w = r.f64(), x = r.f64(), y = r.f64(), z = r.f64();
      out.pose.orientation = Quat(w, x, y, z);
      out.buttons = r.u32();
      break;
    }
    case MessageType::kForce:
      for (int i = 0; i < 3; ++i) out.force_N[i] = r.f64();
      out.ack_sequence = r.u32();
      out.status = r.u32();
      break;
    case MessageType::kEndOfAttempt:
    case MessageType::kAttemptOver:
      out.reason = static_cast<EndReason>(r.u32());
      break;
    case MessageType::kHello:
    case MessageType::kWelcome:
      out.nonce = r.u32();
      break;
  }
  return DecodeError::kNone;
}

}  // namespace acdr::bridge
