// Device input and force-output safety rules.
#include "engine/devices/device_guard.hpp"

#include <algorithm>
#include <cmath>

namespace acdr {

Vec3 clamp_and_slew(const Vec3& requested_N, const Vec3& last_N, double max_N, double max_change_N,
                    bool* clamped) {
  Vec3 f = requested_N;
  const double mag = f.norm();
  *clamped = mag > max_N;
  // Scaled a hair below the limit so rounding never leaves it above.
  if (*clamped) f *= (max_N / mag) * (1.0 - 1e-14);
  const Vec3 change = f - last_N;
  if (change.norm() > max_change_N) f = last_N + change * (max_change_N / change.norm());
  return f;
}
namespace {

bool finite_pose(const Pose& p) {
  return p.position.allFinite() && p.orientation.coeffs().allFinite() &&
         p.orientation.norm() > 1e-6;
}

}  // namespace

DeviceGuard::DeviceGuard(const DeviceConfig& device, const Pose& start, double dt_s)
    : device_(device), dt_(dt_s), target_(start), accepted_(start), candidate_(start) {}

GuardedInput DeviceGuard::accept(const Pose& raw) {
  GuardedInput out;
  if (!finite_pose(raw)) {
    out.accepted = false;
    out.non_finite = true;
    rejecting_ = true;
  } else {
    Pose sample = raw;
    sample.orientation.normalize();
    const double jump = (sample.position - accepted_.position).norm();
    if (jump <= device_.max_jump_m) {
      accepted_ = sample;
      if (rejecting_) ramp_start_s_ = -1.0;  // restart the ramp at the next limit() call
      rejecting_ = false;
      candidate_count_ = 0;
    } else {
      // A jump: hold the target. Accept the new place only once the device has stayed there.
      const bool consistent = (sample.position - candidate_.position).norm() <= device_.max_jump_m;
      candidate_count_ = consistent ? candidate_count_ + 1 : 1;
      candidate_ = sample;
      if (candidate_count_ >= kSettleSamples) {
        accepted_ = sample;
        candidate_count_ = 0;
        ramp_start_s_ = -1.0;
        rejecting_ = false;
      } else {
        out.accepted = false;
        out.jump_m = jump;
        rejecting_ = true;
      }
    }
  }

  // Slew the coupling target toward the accepted pose at a bounded speed, so that even an
  // accepted relocation moves the instrument at most kMaxTargetSpeed.
  const Vec3 delta = accepted_.position - target_.position;
  const double max_step = kMaxTargetSpeed * dt_;
  const double dist = delta.norm();
  const Vec3 step = dist > max_step ? delta * (max_step / dist) : delta;
  const Pose previous = target_;
  target_.position += step;
  target_.orientation = accepted_.orientation;
  if (target_.orientation.dot(previous.orientation) < 0.0) target_.orientation.coeffs() *= -1.0;
  out.target = target_;
  out.target_velocity = step / dt_;
  return out;
}

GuardedInput DeviceGuard::accept_lost() {
  rejecting_ = true;
  candidate_count_ = 0;
  GuardedInput out;
  out.accepted = false;
  out.target = target_;
  out.target_velocity = Vec3::Zero();
  return out;
}

GuardedForce DeviceGuard::limit(const Vec3& requested_N, double t_s) {
  GuardedForce out;
  if (ramp_start_s_ < 0.0) ramp_start_s_ = t_s;
  out.requested_N = requested_N.norm();
  Vec3 f = requested_N;
  if (rejecting_ || !f.allFinite()) f.setZero();

  // Ramp in: scale from 0 to 1 over ramp_in_s after start or after a rejection.
  if (device_.ramp_in_s > 0.0) {
    const double ramp = std::clamp((t_s - ramp_start_s_) / device_.ramp_in_s, 0.0, 1.0);
    f *= ramp;
  }
  f = clamp_and_slew(f, last_force_, device_.max_force_N, device_.max_force_rate_N_s * dt_,
                     &out.clamped);
  last_force_ = f;
  out.force_N = f;
  return out;
}

}  // namespace acdr
