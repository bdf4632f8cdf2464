// UDP bridge input device.
#include "engine/devices/udp_device.hpp"

#include <array>
#include <cstring>
#include <random>

namespace acdr {

bridge::EndReason end_reason_from_text(const char* reason) {
  using bridge::EndReason;
  if (!reason) return EndReason::kUnspecified;
  const std::string r = reason;
  if (r == "time limit") return EndReason::kTimeLimit;
  if (r == "input ended") return EndReason::kInputEnded;
  if (r == "stopped") return EndReason::kStopped;
  if (r == "numerical failure") return EndReason::kNumericalFailure;
  if (r == "device disconnected") return EndReason::kDisconnected;
  return EndReason::kUnspecified;
}

std::unique_ptr<UdpDevice> UdpDevice::open(const UdpDeviceOptions& options, std::string* error) {
  std::unique_ptr<UdpDevice> d(new UdpDevice(options));
  d->socket_ = UdpSocket::bind(options.host, options.port, error);
  if (!d->socket_) return nullptr;
  d->opened_ = Clock::now();
  d->last_packet_ = d->opened_;
  // The session number: from the system's entropy source, so another local program cannot
  // predict it; drawn here, not on the haptic thread.
  std::random_device entropy;
  while (d->session_ == 0) d->session_ = entropy();
  return d;
}

bool UdpDevice::drain(Clock::time_point now) {
  std::array<std::uint8_t, bridge::kMaxMessageSize + 1> buffer;
  bool fresh = false;
  std::int64_t received = 0, lost = 0, late = 0, malformed = 0, foreign = 0;
  std::string foreign_sender;
  bool end = false;
  std::string malformed_detail;
  for (;;) {
    UdpEndpoint from;
    const long n = socket_->receive(buffer, &from);
    if (n <= 0) break;
    bridge::Message m;
    // A datagram longer than the buffer is reported at its full length and fails the size check.
    const std::size_t size = static_cast<std::size_t>(n);
    std::string detail;
    const bridge::DecodeError e =
        size > buffer.size()
            ? bridge::DecodeError::kBadSize
            : bridge::decode(std::span<const std::uint8_t>(buffer.data(), size), m, &detail);
    if (e != bridge::DecodeError::kNone) {
      ++malformed;
      malformed_detail = size > buffer.size() ? "datagram of " + std::to_string(size) + " bytes"
                                              : detail;
      continue;
    }
    if (m.type == bridge::MessageType::kHello) {
      // The first hello opens the session; the same bridge's hello again (our welcome was
      // lost) is answered again; anyone else's is not.
      if (!bridge_.valid) {
        bridge_ = from;
        bridge_nonce_ = m.nonce;
      }
      if (bridge_.same_as(from) && m.nonce == bridge_nonce_ && !finished_) {
        welcome();
      } else {
        ++foreign;
        foreign_sender = from.to_string();
      }
      continue;
    }
    const bool from_bridge = bridge_.same_as(from) && m.session == session_;
    if ((m.type == bridge::MessageType::kPose || m.type == bridge::MessageType::kEndOfAttempt) &&
        !from_bridge) {
      ++foreign;
      foreign_sender = from.to_string();
      continue;
    }
    if (m.type == bridge::MessageType::kPose) {
      ++received;
      last_packet_ = now;
      if (have_pose_) {
        const auto ahead = static_cast<std::int32_t>(m.sequence - last_sequence_);
        if (ahead <= 0) {
          ++late;
          continue;
        }
        lost += ahead - 1;
      }
      last_sequence_ = m.sequence;
      pose_ = m.pose;
      // Each press of the second button asks for the next instrument on the tray.
      if ((m.buttons & 2u) != 0 && (buttons_ & 2u) == 0) ++instrument_presses_;
      buttons_ = m.buttons;
      have_pose_ = true;
      fresh = true;
      // A non-finite pose is delivered on its own (the rest waits for the next sample), so the
      // simulation's guard sees it, rejects it and records it even when the next pose is
      // already queued behind it.
      if (!pose_.position.allFinite() || !pose_.orientation.coeffs().allFinite()) break;
    } else if (m.type == bridge::MessageType::kEndOfAttempt) {
      ++received;
      last_packet_ = now;
      end = true;
    } else {
      ++malformed;  // force or attempt-over sent to the simulator: wrong direction
      malformed_detail = "message type " + std::to_string(static_cast<int>(m.type)) +
                         " is for the bridge, not the simulator";
    }
  }
  if (received || malformed || foreign) {
    std::lock_guard lock(stats_mutex_);
    stats_.packets_received += received;
    stats_.packets_lost += lost;
    stats_.packets_late += late;
    stats_.packets_malformed += malformed;
    stats_.packets_foreign += foreign;
    if (malformed) stats_.last_malformed = malformed_detail;
    if (foreign) stats_.last_foreign = foreign_sender;
    if (end) stats_.end_of_attempt = true;
    if (have_pose_ && !stats_.connected) {
      stats_.connected = true;
      stats_.bridge = bridge_.to_string();
    }
  }
  return fresh;
}

bool UdpDevice::wait_for_connection(double timeout_s) {
  const auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s);
  for (;;) {
    drain(Clock::now());
    if (have_pose_) {
      opened_ = last_packet_;
      return true;
    }
    const double left = std::chrono::duration<double>(deadline - Clock::now()).count();
    if (left <= 0) return false;
    socket_->wait_readable(std::min(left, 0.05));
  }
}

bool UdpDevice::sample(double t_s, DeviceSample& out) {
  const auto now = Clock::now();
  drain(now);
  const double silence = std::chrono::duration<double>(now - last_packet_).count();
  const bool disconnected = silence > options_.disconnect_timeout_s;
  bool end_received;
  {
    std::lock_guard lock(stats_mutex_);
    end_received = stats_.end_of_attempt;
    if (have_pose_ && silence > stats_.longest_silence_s) stats_.longest_silence_s = silence;
    if (disconnected) stats_.disconnected = true;
    const bool stale = silence > options_.silence_limit_s;
    if (stale && !stale_) ++stats_.silences;
    stale_ = stale;
  }
  if (!have_pose_) {
    // Nothing to follow yet: the start pose stays in force until the bridge speaks or the
    // disconnect timeout passes.
    if (!disconnected && !end_received) return false;
    out.disconnected = disconnected;
    out.end = end_received;
    out.stale = true;
    out.silence_s = silence;
    return true;
  }
  out.t_s = t_s;
  out.pose = pose_;
  out.buttons = buttons_;
  // The first button closes the instrument's jaws (World rate-limits the closing).
  out.grip = (buttons_ & 1u) != 0 ? 1.0 : 0.0;
  // The second button's presses walk through the tray (World takes the count modulo its size).
  out.instrument = instrument_presses_;
  out.end = end_received;
  out.stale = stale_;
  out.disconnected = disconnected;
  out.silence_s = silence;
  return true;
}

void UdpDevice::send(bridge::Message m) {
  m.session = session_;
  std::array<std::uint8_t, bridge::kMaxMessageSize> buffer;
  const std::size_t n = bridge::encode(m, buffer);
  const bool ok = socket_->send_to(bridge_, std::span<const std::uint8_t>(buffer.data(), n));
  std::lock_guard lock(stats_mutex_);
  if (!ok) ++stats_.send_errors;
  if (ok && m.type == bridge::MessageType::kForce) {
    ++stats_.forces_sent;
    const double f = m.force_N.norm();
    if (f > stats_.max_force_sent_N) stats_.max_force_sent_N = f;
  }
}

void UdpDevice::welcome() {
  bridge::Message m;
  m.type = bridge::MessageType::kWelcome;
  m.sequence = out_sequence_++;
  m.timestamp_s = std::chrono::duration<double>(Clock::now() - opened_).count();
  m.nonce = bridge_nonce_;
  send(m);
}

void UdpDevice::render_force(const Vec3& force_N) {
  if (!bridge_.valid || !have_pose_ || finished_) return;
  bridge::Message m;
  m.type = bridge::MessageType::kForce;
  m.sequence = out_sequence_++;
  m.timestamp_s = std::chrono::duration<double>(Clock::now() - opened_).count();
  // Never send a non-finite force, whatever happened upstream.
  m.force_N = force_N.allFinite() ? force_N : Vec3::Zero();
  m.ack_sequence = last_sequence_;
  m.status = bridge::kStatusRunning | (stale_ ? bridge::kStatusForceZeroed : 0u);
  send(m);
}

void UdpDevice::finish(const char* reason) {
  if (finished_) return;
  finished_ = true;
  if (!bridge_.valid) return;
  bridge::Message m;
  m.type = bridge::MessageType::kAttemptOver;
  m.sequence = out_sequence_++;
  m.timestamp_s = std::chrono::duration<double>(Clock::now() - opened_).count();
  m.reason = end_reason_from_text(reason);
  for (int copy = 0; copy < 3; ++copy) send(m);
}

UdpDeviceStats UdpDevice::stats() const {
  std::lock_guard lock(stats_mutex_);
  return stats_;
}

}  // namespace acdr
