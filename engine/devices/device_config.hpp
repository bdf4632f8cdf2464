// What a scene says about the haptic device the force is sent to (plain data, SI units).
#pragma once

#include <string>

namespace acdr {

/// The haptic device the force is sent to (docs/references.md, Haptics).
struct DeviceConfig {
  std::string name = "Touch";
  double max_force_N = 3.3;
  double max_force_rate_N_s = 300.0;  ///< slew limit of the rendered force
  double ramp_in_s = 0.5;             ///< force ramps from zero at start (no start-up kick)
  double max_jump_m = 0.01;           ///< a pose jump larger than this in one packet is rejected
};

}  // namespace acdr
