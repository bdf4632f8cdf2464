// The haptic bridge protocol (version 2): fixed-size little-endian UDP datagrams between a
// device bridge (a small program next to the haptic device's driver) and the simulator.
//   bridge -> simulator: kHello until welcomed, then kPose at the device rate (>= 1 kHz),
//                        kEndOfAttempt once at the end;
//   simulator -> bridge: kWelcome (the session), kForce after every device tick, kAttemptOver
//                        when the attempt ends.
// A session belongs to the bridge that opened it: the simulator answers the first hello with a
// random session number, and from then on takes poses only from that bridge's address and
// port carrying that number (every message's header carries it); other senders are counted
// and ignored. Version 1 had no session (the newest sender took over) and is refused.
// The byte layout is specified in docs/haptic-bridge.md so that a lab can write a bridge in any
// language; this file is our reference encoder and decoder.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "engine/core/types.hpp"

namespace acdr::bridge {

/// The first four bytes of every message: "ACDH" (ACDR Haptics).
inline constexpr std::array<std::uint8_t, 4> kMagic = {'A', 'C', 'D', 'H'};
/// Protocol version. A receiver rejects any other version (no silent misreading).
inline constexpr std::uint16_t kVersion = 2;

enum class MessageType : std::uint8_t {
  kPose = 1,          ///< bridge -> simulator: device pose and buttons
  kForce = 2,         ///< simulator -> bridge: force to render
  kEndOfAttempt = 3,  ///< bridge -> simulator: the user (or a trajectory) has finished
  kAttemptOver = 4,   ///< simulator -> bridge: the attempt ended (time limit, end, failure)
  kHello = 5,         ///< bridge -> simulator: asks for a session (its own nonce inside)
  kWelcome = 6,       ///< simulator -> bridge: the session number, and the bridge's nonce back
};

/// Sizes in bytes of each message (header included).
inline constexpr std::size_t kHeaderSize = 24;
inline constexpr std::size_t kPoseSize = kHeaderSize + 7 * 8 + 8;  // 88
inline constexpr std::size_t kForceSize = kHeaderSize + 3 * 8 + 8;  // 56
inline constexpr std::size_t kEndSize = kHeaderSize + 8;            // 32 (both end messages)
inline constexpr std::size_t kHelloSize = kHeaderSize + 8;          // 32 (hello and welcome)
inline constexpr std::size_t kMaxMessageSize = kPoseSize;

/// Bits of ForceMessage::status.
inline constexpr std::uint32_t kStatusRunning = 1u << 0;       ///< the attempt is running
inline constexpr std::uint32_t kStatusForceZeroed = 1u << 1;   ///< safety has zeroed the force
inline constexpr std::uint32_t kStatusAttemptOver = 1u << 2;   ///< no more steps will follow

/// Reasons in end messages.
enum class EndReason : std::uint32_t {
  kUnspecified = 0,
  kUserFinished = 1,    ///< kEndOfAttempt: the user pressed "done" / the trajectory ended
  kTimeLimit = 2,       ///< kAttemptOver: the scenario's time limit passed
  kInputEnded = 3,      ///< kAttemptOver: the bridge's end-of-attempt was received
  kStopped = 4,         ///< kAttemptOver: stopped in the simulator (window closed)
  kNumericalFailure = 5,
  kDisconnected = 6,    ///< kAttemptOver: the simulator heard nothing for its timeout
};

/// One decoded message. Which fields mean something depends on `type`:
/// kPose: pose, buttons; kForce: force_N, ack_sequence, status; end messages: reason; hello
/// and welcome: nonce.
struct Message {
  MessageType type = MessageType::kPose;
  std::uint32_t sequence = 0;  ///< per sender, +1 per message; gaps mean lost packets
  /// The session the message belongs to (the simulator's number from kWelcome); 0 in kHello.
  std::uint32_t session = 0;
  double timestamp_s = 0.0;    ///< sender's clock (s), informative (round-trip measurement)
  Pose pose;                   ///< grip pose, world frame: position (m), unit quaternion
  std::uint32_t buttons = 0;   ///< bit i = button i pressed
  Vec3 force_N = Vec3::Zero(); ///< force the device should render (N), already clamped
  std::uint32_t ack_sequence = 0;  ///< newest pose sequence the simulator had used
  std::uint32_t status = 0;        ///< kStatus* bits
  EndReason reason = EndReason::kUnspecified;
  /// kHello: a random number of the bridge's; kWelcome: that number back, so the bridge knows
  /// the welcome answers its own hello.
  std::uint32_t nonce = 0;
};

/// Size of a message of this type in bytes.
std::size_t message_size(MessageType type);

/// Encodes `m` into `out` (at least message_size(m.type) bytes); returns the size written.
std::size_t encode(const Message& m, std::span<std::uint8_t> out);

/// What went wrong with a datagram.
enum class DecodeError {
  kNone = 0,
  kTooShort,      ///< shorter than a header
  kBadMagic,
  kBadVersion,
  kUnknownType,
  kBadSize,       ///< the size does not match the type
};
const char* decode_error_name(DecodeError e);

/// Decodes one datagram. The layout is checked (magic, version, type, exact size); values are
/// not: a pose with NaN decodes as such, and the simulator's input guard rejects it as an
/// event (so that device faults are recorded, not hidden). On error `out` is unspecified and
/// `detail` (when given) says what was found and what was expected.
DecodeError decode(std::span<const std::uint8_t> bytes, Message& out,
                   std::string* detail = nullptr);

}  // namespace acdr::bridge
