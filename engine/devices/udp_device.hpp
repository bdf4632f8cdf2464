// An input device on the UDP haptic bridge (engine/devices/udp_bridge_protocol.hpp): the simulator
// binds a loopback port, welcomes the first bridge that says hello into a session of its own
// (a random session number), takes the newest pose of that bridge each step, answers each step
// with the force to render, and watches the link:
//  - only the session's bridge (its address and port, and the session number in each message)
//    is heard; anyone else's datagrams are counted (packets_foreign) and ignored, never
//    answered;
//  - sequence gaps are counted as lost packets, older or repeated packets are dropped;
//  - no packet for `silence_limit_s` (default 50 ms): the sample is marked stale, so the World
//    holds the instrument and zeroes the force (recorded as an input_lost event);
//  - no packet for `disconnect_timeout_s` (default 5 s): the sample is marked disconnected and
//    the attempt ends (recorded as device_disconnected);
//  - an end-of-attempt message ends the attempt normally.
// sample(), render_force() and finish() are called from the haptic thread; stats() may be
// called from any thread (a short lock around a copy).
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include "engine/devices/input_device.hpp"
#include "engine/devices/udp_bridge_protocol.hpp"
#include "engine/devices/udp_socket.hpp"

namespace acdr {

struct UdpDeviceOptions {
  std::string host = "127.0.0.1";  ///< loopback by default: the bridge runs on this machine
  int port = 0;                    ///< 0: the system picks one (tests); see UdpDevice::port()
  /// No packet for this long: force zeroed and pose held (50 ms = 50 packets at 1 kHz).
  double silence_limit_s = 0.05;
  /// No packet for this long: the device counts as disconnected and the attempt ends.
  double disconnect_timeout_s = 5.0;
};

/// What the link did, for the `haptics` report and the trainee view.
struct UdpDeviceStats {
  std::int64_t packets_received = 0;   ///< valid messages from the bridge
  std::int64_t packets_lost = 0;       ///< missing sequence numbers (gaps)
  std::int64_t packets_late = 0;       ///< reordered or repeated poses, dropped
  std::int64_t packets_malformed = 0;  ///< datagrams that failed to decode, or wrong direction
  /// Well-formed datagrams from anyone but the session's bridge (another address or port, or
  /// not the session's number), ignored.
  std::int64_t packets_foreign = 0;
  std::int64_t forces_sent = 0;
  std::int64_t send_errors = 0;
  std::int64_t silences = 0;           ///< times the silence limit passed (force zeroed)
  double longest_silence_s = 0.0;      ///< longest gap between packets once connected (s)
  double max_force_sent_N = 0.0;       ///< largest force magnitude sent to the bridge (N)
  bool connected = false;              ///< a first pose has arrived
  bool end_of_attempt = false;         ///< the bridge sent end-of-attempt
  bool disconnected = false;           ///< the disconnect timeout passed
  std::string bridge;                  ///< the bridge's address, "host:port"
  std::string last_malformed;          ///< what was wrong with the last malformed datagram
  std::string last_foreign;            ///< who sent the last foreign datagram, "host:port"
};

class UdpDevice final : public InputDevice {
 public:
  /// Binds host:port. Null and an error (port in use, bad address) on failure.
  static std::unique_ptr<UdpDevice> open(const UdpDeviceOptions& options, std::string* error);

  int port() const { return socket_->local_port(); }
  const UdpDeviceOptions& options() const { return options_; }

  /// Blocks until the bridge's first pose arrives (true) or `timeout_s` passes (false), answering
  /// its hello meanwhile. Call before the attempt starts, so the attempt's clock starts with
  /// the device.
  bool wait_for_connection(double timeout_s);

  bool sample(double t_s, DeviceSample& out) override;
  void render_force(const Vec3& force_N) override;
  /// Sends attempt-over to the bridge (three copies, as UDP may drop one).
  void finish(const char* reason) override;
  bool live() const override { return true; }

  UdpDeviceStats stats() const;

 private:
  using Clock = std::chrono::steady_clock;
  explicit UdpDevice(const UdpDeviceOptions& options) : options_(options) {}
  // Reads every waiting datagram; returns true if a newer pose arrived.
  bool drain(Clock::time_point now);
  void send(bridge::Message m);
  void welcome();

  UdpDeviceOptions options_;
  std::unique_ptr<UdpSocket> socket_;
  UdpEndpoint bridge_;              ///< the session's bridge (invalid until a hello)
  std::uint32_t session_ = 0;       ///< the session number, random, never 0
  std::uint32_t bridge_nonce_ = 0;  ///< the nonce of the hello that opened the session
  Clock::time_point opened_;
  Clock::time_point last_packet_;
  Pose pose_;
  std::uint32_t buttons_ = 0;
  int instrument_presses_ = 0;  // presses of the second button so far
  bool have_pose_ = false;
  std::uint32_t last_sequence_ = 0;
  std::uint32_t out_sequence_ = 0;
  bool stale_ = false;
  bool finished_ = false;

  mutable std::mutex stats_mutex_;
  UdpDeviceStats stats_;  ///< guarded by stats_mutex_
};

/// The attempt-over reason code for a reason in words ("time limit", "input ended", ...).
bridge::EndReason end_reason_from_text(const char* reason);

}  // namespace acdr
