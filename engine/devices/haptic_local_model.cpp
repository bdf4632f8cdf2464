// Local force model of the device loop (see the header).
#include "engine/devices/haptic_local_model.hpp"

#include "engine/devices/device_guard.hpp"

namespace acdr {

HapticLocalModel::HapticLocalModel(const DeviceConfig& device, double coupling_stiffness_N_m,
                                   double tick_s)
    : device_(device), k_(coupling_stiffness_N_m), tick_s_(tick_s) {}

LocalForce HapticLocalModel::force(const PhysicsForce& physics, const Vec3& device_position_m,
                                   bool stale) {
  LocalForce out;
  const Vec3 dx = device_position_m - physics.device_position_m;
  if (!physics.valid || stale || !device_position_m.allFinite() ||
      !physics.force_N.allFinite() || !(dx.norm() <= device_.max_jump_m)) {
    // Nothing trustworthy to render: zero at once (not slewed), as the World does.
    out.zeroed = true;
    last_ = Vec3::Zero();
    return out;
  }
  const Vec3 f = clamp_and_slew(physics.force_N - k_ * dx, last_, device_.max_force_N,
                                device_.max_force_rate_N_s * tick_s_, &out.clamped);
  last_ = f;
  out.force_N = f;
  return out;
}

}  // namespace acdr
