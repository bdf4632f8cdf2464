// Virtual haptic device on the bridge protocol.
#include "engine/devices/virtual_bridge.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <thread>

#include "engine/devices/udp_socket.hpp"

namespace acdr {
namespace {

using Clock = std::chrono::steady_clock;

// Sends, receives and logs on one socket; shared by the connect, play and linger phases.
class Link {
 public:
  Link(UdpSocket& socket, const UdpEndpoint& simulator, const VirtualBridgeOptions& options,
       VirtualBridgeResult& result)
      : socket_(socket), simulator_(simulator), options_(options), result_(result) {}

  void send(bridge::Message m) {
    m.sequence = sequence_++;
    std::array<std::uint8_t, bridge::kMaxMessageSize> buffer;
    const std::size_t n = bridge::encode(m, buffer);
    if (socket_.send_to(simulator_, std::span<const std::uint8_t>(buffer.data(), n)) &&
        m.type == bridge::MessageType::kPose)
      ++result_.poses_sent;
  }
  /// Skips a sequence number without sending (a lost packet, as the simulator sees it).
  void drop() {
    ++sequence_;
    ++result_.poses_dropped;
  }

  void receive_all(double t_s) {
    std::array<std::uint8_t, bridge::kMaxMessageSize + 1> buffer;
    for (;;) {
      const long n = socket_.receive(buffer, nullptr);
      if (n <= 0) return;
      bridge::Message m;
      if (static_cast<std::size_t>(n) > bridge::kMaxMessageSize ||
          bridge::decode(std::span<const std::uint8_t>(buffer.data(), static_cast<std::size_t>(n)),
                         m) != bridge::DecodeError::kNone)
        continue;
      if (m.type == bridge::MessageType::kForce) {
        result_.connected = true;
        if (result_.forces_received > 0) {
          const auto ahead = static_cast<std::int32_t>(m.sequence - last_force_sequence_);
          if (ahead > 1) result_.forces_lost += ahead - 1;
        }
        last_force_sequence_ = m.sequence;
        ++result_.forces_received;
        result_.max_force_N = std::max(result_.max_force_N, m.force_N.norm());
        if (options_.log_forces)
          result_.forces.push_back({t_s, m.sequence, m.ack_sequence, m.force_N, m.status});
        if (m.status & bridge::kStatusAttemptOver) result_.attempt_over = true;
      } else if (m.type == bridge::MessageType::kAttemptOver) {
        result_.connected = true;
        result_.attempt_over = true;
        result_.attempt_over_reason = m.reason;
      }
    }
  }

 private:
  UdpSocket& socket_;
  UdpEndpoint simulator_;
  const VirtualBridgeOptions& options_;
  VirtualBridgeResult& result_;
  std::uint32_t sequence_ = 0;
  std::uint32_t last_force_sequence_ = 0;
};

bridge::Message pose_message(const Pose& pose, double t_s) {
  bridge::Message m;
  m.type = bridge::MessageType::kPose;
  m.timestamp_s = t_s;
  m.pose = pose;
  return m;
}

}  // namespace

VirtualBridge::VirtualBridge(Trajectory trajectory, const VirtualBridgeOptions& options)
    : trajectory_(std::move(trajectory)), options_(options) {}

VirtualBridgeResult VirtualBridge::run(const std::atomic<bool>* stop) {
  VirtualBridgeResult result;
  const UdpEndpoint simulator = make_endpoint(options_.host, options_.port);
  if (!simulator.valid || options_.port <= 0) {
    result.error = "device-sim: bad simulator address " + options_.host + ":" +
                   std::to_string(options_.port);
    return result;
  }
  auto socket = UdpSocket::bind("0.0.0.0", 0, &result.error);
  if (!socket) return result;
  Link link(*socket, simulator, options_, result);
  if (options_.log_forces)
    result.forces.reserve(static_cast<std::size_t>(
        (trajectory_.duration_s() + options_.linger_s + 1.0) * options_.rate_hz * 1.5));
  auto stopped = [&] { return stop && stop->load(std::memory_order_relaxed); };

  // Connect: repeat the start pose until the simulator answers with a force.
  const Pose start = trajectory_.at(0.0);
  const auto give_up = Clock::now() + std::chrono::duration<double>(options_.connect_timeout_s);
  while (!result.connected && !stopped()) {
    link.send(pose_message(start, 0.0));
    socket->wait_readable(0.01);
    link.receive_all(0.0);
    if (Clock::now() > give_up) {
      result.error = "device-sim: no answer from the simulator at " + simulator.to_string() +
                     " within " + std::to_string(options_.connect_timeout_s) + " s";
      return result;
    }
  }
  if (stopped()) return result;

  // Play at the fixed rate on a haptic loop (the same pacing as the simulator's).
  HapticLoopOptions loop_options;
  loop_options.rate_hz = options_.rate_hz;
  loop_options.realtime_priority = options_.realtime_priority;
  HapticLoop loop(loop_options);
  const double duration = trajectory_.duration_s();
  const double dt = 1.0 / options_.rate_hz;
  std::int64_t tick = 0;
  loop.start([&]() {
    const double t = static_cast<double>(tick++) * dt;
    result.played_s = std::min(t, duration);
    link.receive_all(t);
    if (result.attempt_over || stopped()) return false;
    if (t > duration) {
      bridge::Message end;
      end.type = bridge::MessageType::kEndOfAttempt;
      end.timestamp_s = t;
      end.reason = bridge::EndReason::kUserFinished;
      for (int copy = 0; copy < 3; ++copy) link.send(end);
      result.sent_end = true;
      return false;
    }
    // Fault injection.
    const bool silent = options_.silence_at_s >= 0 && t >= options_.silence_at_s &&
                        t < options_.silence_at_s + options_.silence_for_s;
    if (silent || (options_.drop_every > 0 && tick % options_.drop_every == 0)) {
      link.drop();
      return true;
    }
    Pose pose = trajectory_.at(t);
    if (options_.nan_at_s >= 0 && t >= options_.nan_at_s &&
        t < options_.nan_at_s + std::max(0.5 * dt, options_.nan_for_s))
      pose.position.x() = std::numeric_limits<double>::quiet_NaN();
    if (options_.jump_at_s >= 0 && t >= options_.jump_at_s &&
        t < options_.jump_at_s + options_.jump_for_s)
      pose.position.x() += options_.jump_m;
    link.send(pose_message(pose, t));
    return true;
  });
  loop.join();
  result.loop = loop.stats();

  // Linger for the simulator's attempt-over (and the last forces).
  const auto linger_end = Clock::now() + std::chrono::duration<double>(options_.linger_s);
  while (!result.attempt_over && !stopped() && Clock::now() < linger_end) {
    socket->wait_readable(0.01);
    link.receive_all(result.played_s);
  }
  return result;
}

}  // namespace acdr
