// Virtual haptic device on the bridge protocol.
#include "engine/devices/virtual_bridge.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>
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
    m.session = result_.session;
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

  void hello(std::uint32_t nonce) {
    bridge::Message m;
    m.type = bridge::MessageType::kHello;
    m.nonce = nonce;
    send(m);
  }

  // Reads every waiting datagram. Before the session: only our simulator's welcome to our
  // hello counts; after: only its messages of that session.
  void receive_all(double t_s, std::uint32_t hello_nonce = 0) {
    std::array<std::uint8_t, bridge::kMaxMessageSize + 1> buffer;
    for (;;) {
      UdpEndpoint from;
      const long n = socket_.receive(buffer, &from);
      if (n <= 0) return;
      bridge::Message m;
      if (static_cast<std::size_t>(n) > bridge::kMaxMessageSize ||
          bridge::decode(std::span<const std::uint8_t>(buffer.data(), static_cast<std::size_t>(n)),
                         m) != bridge::DecodeError::kNone)
        continue;
      if (!from.same_as(simulator_)) {
        ++result_.packets_foreign;
        continue;
      }
      if (m.type == bridge::MessageType::kWelcome && result_.session == 0 &&
          hello_nonce != 0 && m.nonce == hello_nonce && m.session != 0) {
        result_.session = m.session;
        continue;
      }
      if (result_.session == 0 || m.session != result_.session) {
        if (m.type != bridge::MessageType::kWelcome) ++result_.packets_foreign;
        continue;
      }
      if (m.type == bridge::MessageType::kForce) {
        result_.connected = true;
        result_.last_force_at_s = t_s;
        last_force_ = Clock::now();
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

  // Seconds since the last force (since the session began, before the first).
  double since_last_force() const {
    return std::chrono::duration<double>(Clock::now() - last_force_).count();
  }
  void start_force_clock() { last_force_ = Clock::now(); }

 private:
  UdpSocket& socket_;
  UdpEndpoint simulator_;
  const VirtualBridgeOptions& options_;
  VirtualBridgeResult& result_;
  std::uint32_t sequence_ = 0;
  std::uint32_t last_force_sequence_ = 0;
  Clock::time_point last_force_ = Clock::now();
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

  // Connect: say hello until the simulator welcomes us into a session, then repeat the start
  // pose until it answers with a force.
  std::uint32_t nonce = 0;
  std::random_device entropy;
  while (nonce == 0) nonce = entropy();
  const Pose start = trajectory_.at(0.0);
  const auto give_up = Clock::now() + std::chrono::duration<double>(options_.connect_timeout_s);
  while (!result.connected && !stopped()) {
    if (result.session == 0)
      link.hello(nonce);
    else
      link.send(pose_message(start, 0.0));
    socket->wait_readable(0.01);
    link.receive_all(0.0, nonce);
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
  link.start_force_clock();
  loop.start([&]() {
    const double t = static_cast<double>(tick++) * dt;
    result.played_s = std::min(t, duration);
    link.receive_all(t);
    if (result.attempt_over || stopped()) return false;
    if (link.since_last_force() > options_.peer_timeout_s) {
      // The simulator is gone (killed, crashed): nobody renders our poses any more.
      result.peer_lost = true;
      result.connected = false;
      return false;
    }
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
  while (!result.peer_lost && !result.attempt_over && !stopped() &&
         Clock::now() < linger_end) {
    socket->wait_readable(0.01);
    link.receive_all(result.played_s);
  }
  return result;
}

}  // namespace acdr
