// Local force model of the device loop (see the header).
#include "engine/haptic_local_model.hpp"

#include <algorithm>

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
  Vec3 f = physics.force_N - k_ * dx;
  const double magnitude = f.norm();
  if (magnitude > device_.max_force_N) {
    // Scaled a hair below the limit so rounding never leaves it above.
    f *= (device_.max_force_N / magnitude) * (1.0 - 1e-12);
    out.clamped = true;
  }
  // Slew: the change per tick is bounded by the device's force-rate limit.
  const Vec3 step = f - last_;
  const double max_step = device_.max_force_rate_N_s * tick_s_;
  if (step.norm() > max_step) f = last_ + step * (max_step / step.norm());
  last_ = f;
  out.force_N = f;
  return out;
}

}  // namespace acdr
