// `acdr device-sim --port P --trajectory FILE`: a virtual haptic device on the UDP bridge
// protocol (engine/devices/virtual_bridge.hpp), for testing bridges, the haptic loop and the safety
// rules without hardware.
#pragma once

#include <iosfwd>
#include <string>

#include "engine/devices/virtual_bridge.hpp"

namespace acdr {

struct DeviceSimOptions {
  std::string trajectory;   ///< trajectory CSV (docs/trajectory-format.md)
  std::string forces_csv;   ///< write the forces received here (t_s,seq,ack,fx,fy,fz,status)
  bool json = false;        ///< print the summary as JSON
  VirtualBridgeOptions bridge;
};

/// Exit codes: 0 the trajectory was played and the simulator answered, 2 bad input (file,
/// address) or no simulator answered.
int run_device_sim(const DeviceSimOptions& options, std::ostream& out, std::ostream& err);

}  // namespace acdr
