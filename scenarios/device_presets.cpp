// The preset table. Values from CHAI3D's CPhantomDevices.cpp as collected in docs/references.md.
#include "scenarios/device_presets.hpp"

namespace acdr {

const std::vector<DevicePreset>& device_presets() {
  static const std::vector<DevicePreset> kPresets = {
      {"Touch", 3.3, 400.0},
      {"Phantom Omni", 3.3, 700.0},
      {"Phantom Desktop", 7.9, 1000.0},
  };
  return kPresets;
}

const DevicePreset* find_device_preset(std::string_view name) {
  for (const DevicePreset& p : device_presets()) {
    if (name == p.name) return &p;
  }
  return nullptr;
}

}  // namespace acdr
