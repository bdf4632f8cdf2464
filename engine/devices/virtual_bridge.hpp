// A virtual haptic device speaking the bridge protocol (engine/devices/udp_bridge_protocol.hpp): it
// plays a recorded trajectory as pose packets at a fixed rate (1 kHz), logs the forces the
// simulator sends back, and sends end-of-attempt when the trajectory ends. `acdr device-sim`
// runs it; tests use it as the far end of a loopback link. It can also inject link faults
// (dropped packets, a silence, a NaN pose, a pose jump) so the safety rules can be exercised
// end to end.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/devices/haptic_loop.hpp"
#include "engine/devices/trajectory.hpp"
#include "engine/devices/udp_bridge_protocol.hpp"

namespace acdr {

struct VirtualBridgeOptions {
  std::string host = "127.0.0.1";  ///< the simulator's address
  int port = 0;                    ///< the simulator's port
  double rate_hz = 1000.0;         ///< pose packets per second
  /// Before playing, the bridge says hello every 10 ms until the simulator welcomes it into a
  /// session, then repeats the start pose every 10 ms until the first force, for at most this
  /// long in all (s).
  double connect_timeout_s = 30.0;
  /// While playing, no force packet from the simulator for this long (s) means it is gone (a
  /// crashed or killed `acdr run`): the bridge stops and says so (VirtualBridgeResult::
  /// peer_lost). The same 5 s as the simulator's own disconnect timeout.
  double peer_timeout_s = 5.0;
  /// After end-of-attempt, how long to wait for the simulator's attempt-over (s).
  double linger_s = 1.0;
  bool log_forces = true;  ///< keep every force received (VirtualBridgeResult::forces)
  bool realtime_priority = false;  ///< real-time priority for the send loop, when granted

  // Fault injection (off by default); times are trajectory times (s).
  int drop_every = 0;              ///< > 0: do not send every n-th pose packet (loss)
  double silence_at_s = -1.0;      ///< >= 0: send nothing from here ...
  double silence_for_s = 0.0;      ///< ... for this long
  double nan_at_s = -1.0;          ///< >= 0: one pose with NaN position at this time
  double nan_for_s = 0.0;          ///< > 0: NaN poses for this long from nan_at_s
  double jump_at_s = -1.0;         ///< >= 0: from here, poses are offset by jump_m along x ...
  double jump_for_s = 0.02;        ///< ... for this long (a glitch; shorter than the settle time)
  double jump_m = 0.05;
};

/// One force packet as received.
struct ReceivedForce {
  double t_s = 0.0;             ///< trajectory time when it arrived (s)
  std::uint32_t sequence = 0;   ///< the simulator's sequence number
  std::uint32_t ack_sequence = 0;
  Vec3 force_N = Vec3::Zero();
  std::uint32_t status = 0;
};

struct VirtualBridgeResult {
  /// The simulator answered and was still answering at the end (false once peer_lost).
  bool connected = false;
  bool peer_lost = false;            ///< no force for peer_timeout_s while playing
  double last_force_at_s = -1.0;     ///< trajectory time of the last force received (s)
  std::uint32_t session = 0;         ///< the session number the simulator gave us
  std::int64_t packets_foreign = 0;  ///< datagrams not from our simulator's session, ignored
  std::int64_t poses_sent = 0;
  std::int64_t poses_dropped = 0;    ///< withheld by fault injection (drop, silence)
  std::int64_t forces_received = 0;
  std::int64_t forces_lost = 0;      ///< gaps in the simulator's sequence numbers
  double max_force_N = 0.0;          ///< largest force magnitude received
  bool attempt_over = false;         ///< the simulator said the attempt ended
  bridge::EndReason attempt_over_reason = bridge::EndReason::kUnspecified;
  bool sent_end = false;             ///< we reached the trajectory's end and said so
  double played_s = 0.0;             ///< trajectory time reached (s)
  HapticLoopStats loop;              ///< the bridge's own send loop
  std::vector<ReceivedForce> forces; ///< when log_forces
  std::string error;                 ///< non-empty when the run could not start
};

class VirtualBridge {
 public:
  VirtualBridge(Trajectory trajectory, const VirtualBridgeOptions& options);

  /// Connects, plays the trajectory, ends the attempt; blocks until done. `stop` (optional)
  /// ends it early from another thread.
  VirtualBridgeResult run(const std::atomic<bool>* stop = nullptr);

 private:
  Trajectory trajectory_;
  VirtualBridgeOptions options_;
};

}  // namespace acdr
