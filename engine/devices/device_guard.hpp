// Safety between the device and the simulation, both ways:
//  - incoming poses: NaN/Inf rejected, jumps beyond a threshold rejected until the device has
//    settled at its new place, the coupling target slewed at a bounded speed;
//  - outgoing force: ramped in at start, clamped to the device's rated maximum, rate limited,
//    zeroed while input is rejected or lost (no fresh device data beyond a silence limit).
#pragma once

#include "engine/core/types.hpp"
#include "engine/devices/device_config.hpp"

namespace acdr {

struct GuardedInput {
  Pose target;         ///< coupling target after filtering
  Vec3 target_velocity = Vec3::Zero();
  bool accepted = true;     ///< this sample was used
  double jump_m = 0.0;      ///< distance of a rejected jump (0 if NaN or accepted)
  bool non_finite = false;  ///< the sample held NaN or Inf
};

struct GuardedForce {
  Vec3 force_N = Vec3::Zero();
  bool clamped = false;        ///< the magnitude limit was hit
  double requested_N = 0.0;    ///< magnitude before limiting
};

/// The device force limits: `requested_N` clamped to `max_N` (never above, not even by
/// rounding; `clamped` says whether it was hit), then its change from `last_N` bounded by
/// `max_change_N` (the force-rate limit times the update period).
Vec3 clamp_and_slew(const Vec3& requested_N, const Vec3& last_N, double max_N, double max_change_N,
                    bool* clamped);

class DeviceGuard {
 public:
  DeviceGuard(const DeviceConfig& device, const Pose& start, double dt_s);

  /// Filters one device pose at the fixed step.
  GuardedInput accept(const Pose& sample);
  /// No fresh device data this step (packets lost beyond the device's silence limit): holds
  /// the coupling target where it is (zero target velocity) and zeroes the force until fresh
  /// data returns; the force then ramps in again, and a hand that moved meanwhile is treated
  /// as a jump (rejected until settled, then slewed).
  GuardedInput accept_lost();
  /// Limits the force to send back, at simulated time t (for the ramp-in).
  GuardedForce limit(const Vec3& requested_N, double t_s);

  /// Maximum speed of the coupling target (m/s): the stress suite's fastest instrument.
  static constexpr double kMaxTargetSpeed = 1.0;
  /// Consecutive consistent samples at a new place before a jump is accepted (50 ms at 1 kHz).
  static constexpr int kSettleSamples = 50;

 private:
  DeviceConfig device_;
  double dt_;
  Pose target_;         ///< current coupling target
  Pose accepted_;       ///< last accepted device pose
  Pose candidate_;      ///< where a rejected jump went
  int candidate_count_ = 0;
  bool rejecting_ = false;
  double ramp_start_s_ = 0.0;  ///< force ramps in from here (start, or after a rejection)
  Vec3 last_force_ = Vec3::Zero();
};

}  // namespace acdr
