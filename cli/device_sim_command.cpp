// `acdr device-sim`.
#include "cli/device_sim_command.hpp"

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <ostream>

namespace acdr {
namespace {

const char* reason_name(bridge::EndReason r) {
  switch (r) {
    case bridge::EndReason::kUnspecified: return "unspecified";
    case bridge::EndReason::kUserFinished: return "user finished";
    case bridge::EndReason::kTimeLimit: return "time limit";
    case bridge::EndReason::kInputEnded: return "input ended";
    case bridge::EndReason::kStopped: return "stopped";
    case bridge::EndReason::kNumericalFailure: return "numerical failure";
    case bridge::EndReason::kDisconnected: return "disconnected";
  }
  return "?";
}

}  // namespace

int run_device_sim(const DeviceSimOptions& options, std::ostream& out, std::ostream& err) {
  std::string error;
  auto trajectory = Trajectory::load_csv(options.trajectory, &error);
  if (!trajectory) {
    err << error << "\n";
    return 2;
  }
  VirtualBridgeOptions bridge = options.bridge;
  bridge.log_forces = !options.forces_csv.empty();
  if (!options.json)
    err << "device-sim: playing " << options.trajectory << " (" << trajectory->duration_s()
        << " s) to " << bridge.host << ":" << bridge.port << " at " << bridge.rate_hz << " Hz\n";
  VirtualBridge device(std::move(*trajectory), bridge);
  const VirtualBridgeResult r = device.run();
  if (!r.error.empty()) {
    err << r.error << "\n";
    return 2;
  }

  if (!options.forces_csv.empty()) {
    std::ofstream csv(options.forces_csv);
    csv << "# forces received by acdr device-sim from the simulator\n";
    csv << "t_s,sequence,ack_sequence,fx_N,fy_N,fz_N,status\n";
    char line[200];
    for (const ReceivedForce& f : r.forces) {
      std::snprintf(line, sizeof line, "%.6f,%u,%u,%.9g,%.9g,%.9g,%u\n", f.t_s, f.sequence,
                    f.ack_sequence, f.force_N.x(), f.force_N.y(), f.force_N.z(), f.status);
      csv << line;
    }
    if (!csv) {
      err << options.forces_csv << ": cannot write the force log\n";
      return 2;
    }
  }

  if (options.json) {
    nlohmann::json j;
    j["connected"] = r.connected;
    j["peer_lost"] = r.peer_lost;
    j["last_force_at_s"] = r.last_force_at_s;
    j["session"] = r.session;
    j["packets_foreign"] = r.packets_foreign;
    j["poses_sent"] = r.poses_sent;
    j["poses_dropped"] = r.poses_dropped;
    j["forces_received"] = r.forces_received;
    j["forces_lost"] = r.forces_lost;
    j["max_force_N"] = r.max_force_N;
    j["played_s"] = r.played_s;
    j["sent_end_of_attempt"] = r.sent_end;
    j["attempt_over"] = r.attempt_over;
    j["attempt_over_reason"] = reason_name(r.attempt_over_reason);
    j["rate_hz"] = r.loop.rate_hz;
    j["period_p99_ms"] = r.loop.period_p99_ms;
    if (!options.forces_csv.empty()) j["forces_csv"] = options.forces_csv;
    out << j.dump(2) << "\n";
  } else {
    char line[300];
    std::snprintf(line, sizeof line,
                  "device-sim: played %.2f s: %lld poses sent at %.1f Hz (p99 period %.3f ms), "
                  "%lld forces received (%lld lost), max force %.3f N; %s%s\n",
                  r.played_s, static_cast<long long>(r.poses_sent), r.loop.rate_hz,
                  r.loop.period_p99_ms, static_cast<long long>(r.forces_received),
                  static_cast<long long>(r.forces_lost), r.max_force_N,
                  r.sent_end ? "sent end-of-attempt" : "stopped early",
                  r.attempt_over ? (std::string(", simulator ended the attempt (") +
                                    reason_name(r.attempt_over_reason) + ")")
                                       .c_str()
                                 : "");
    out << line;
  }
  if (r.peer_lost) {
    char line[200];
    std::snprintf(line, sizeof line,
                  "device-sim: the simulator stopped answering: no force for %g s since "
                  "trajectory time %.3f s (acdr run gone?)\n",
                  bridge.peer_timeout_s, r.last_force_at_s);
    err << line;
    return 1;
  }
  return 0;
}

}  // namespace acdr
