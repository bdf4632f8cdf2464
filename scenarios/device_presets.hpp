// Haptic devices a scenario may name by preset, with their rated figures (docs/references.md,
// Haptics: CHAI3D's CPhantomDevices.cpp). A scenario's explicit values override a preset's.
#pragma once

#include <string_view>
#include <vector>

namespace acdr {

struct DevicePreset {
  const char* name;
  double max_force_N;         ///< rated peak force
  double max_stiffness_N_m;   ///< highest stable rendered stiffness (informative)
};

/// Touch 3.3 N / 400 N/m, Phantom Omni 3.3 N / 700 N/m, Phantom Desktop 7.9 N / 1000 N/m.
const std::vector<DevicePreset>& device_presets();

/// The preset of that exact name, or nullptr.
const DevicePreset* find_device_preset(std::string_view name);

}  // namespace acdr
