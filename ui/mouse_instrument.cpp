// Mouse and keyboard instrument input.
#include "ui/mouse_instrument.hpp"

#include <algorithm>
#include <cmath>

namespace acdr {

void MouseInstrumentDevice::set_pose(const Pose& goal) {
  std::lock_guard lock(mutex_);
  goal_ = goal;
}

Pose MouseInstrumentDevice::pose() const {
  std::lock_guard lock(mutex_);
  return goal_;
}

Pose MouseInstrumentDevice::current() const {
  std::lock_guard lock(mutex_);
  return pose_;
}

void MouseInstrumentDevice::request_end() {
  std::lock_guard lock(mutex_);
  end_ = true;
}

void MouseInstrumentDevice::count_time_by(std::function<double()> clock) {
  std::lock_guard lock(mutex_);
  clock_ = std::move(clock);
  last_t_s_ = -1.0;  // the next sample starts counting on the new clock
}

bool MouseInstrumentDevice::sample(double t_s, DeviceSample& out) {
  std::lock_guard lock(mutex_);
  // Toward the goal, at most the speeds allow since the last sample.
  const double now = clock_ ? clock_() : t_s;
  const double dt = last_t_s_ < 0 ? 0.0 : std::max(0.0, now - last_t_s_);
  last_t_s_ = now;
  const Vec3 to_goal = goal_.position - pose_.position;
  const double reach = speeds_.max_speed_m_s * dt;
  const double distance = to_goal.norm();
  pose_.position = distance <= reach ? goal_.position
                                     : Vec3(pose_.position + to_goal * (reach / distance));
  const double angle = pose_.orientation.angularDistance(goal_.orientation);
  const double turn = speeds_.max_turn_rad_s * dt;
  pose_.orientation = angle <= turn ? goal_.orientation
                                    : pose_.orientation.slerp(turn / angle, goal_.orientation);
  out.t_s = t_s;
  out.pose = pose_;
  out.grip = grip_;
  out.instrument = instrument_presses_;
  out.end = end_;
  return true;
}

void MouseInstrumentDevice::next_instrument() {
  std::lock_guard lock(mutex_);
  ++instrument_presses_;
}

void MouseInstrumentDevice::set_grip(double grip) {
  std::lock_guard lock(mutex_);
  grip_ = grip;
}

Pose apply_mouse_input(const Pose& current, const MouseKeyInput& in, const RenderCamera& camera,
                       const MouseMapping& mapping) {
  Pose next = current;
  if (in.hold) return next;
  // View-relative horizontal axes: the camera's right, and its forward flattened onto the
  // ground plane (so dragging never changes height).
  Eigen::Vector3d forward = (camera.target - camera.eye).cast<double>();
  forward.z() = 0.0;
  if (forward.norm() < 1e-9) forward = Vec3::UnitY();
  forward.normalize();
  const Vec3 right = forward.cross(Vec3::UnitZ()).normalized();

  const double speed_scale = in.fast ? 3.0 : 1.0;
  Vec3 move = (in.drag_dx_px * right - in.drag_dy_px * forward) * mapping.metres_per_px;
  const double vertical = (in.up ? 1.0 : 0.0) - (in.down ? 1.0 : 0.0);
  move.z() += vertical * mapping.vertical_speed_m_s * speed_scale * in.dt_s;
  // Depth: the wheel pushes in (forward) or draws out; a right-drag follows the pointer.
  move.z() -= in.wheel_notches * mapping.depth_per_notch_m;
  move.z() -= in.depth_drag_px * mapping.depth_per_px_m;
  const double length = move.norm();
  if (length > mapping.max_step_m) move *= mapping.max_step_m / length;
  next.position += move;

  // Turns about the grip: tilt about the view's right axis, roll about its forward axis.
  const double turn = mapping.turn_speed_rad_s * speed_scale * in.dt_s;
  double tilt = ((in.tilt_plus ? 1.0 : 0.0) - (in.tilt_minus ? 1.0 : 0.0)) * turn +
                in.turn_dy_px * mapping.turn_per_px_rad;
  double roll = ((in.roll_plus ? 1.0 : 0.0) - (in.roll_minus ? 1.0 : 0.0)) * turn +
                in.turn_dx_px * mapping.turn_per_px_rad;
  tilt = std::clamp(tilt, -mapping.max_turn_rad, mapping.max_turn_rad);
  roll = std::clamp(roll, -mapping.max_turn_rad, mapping.max_turn_rad);
  if (tilt != 0.0 || roll != 0.0) {
    const Quat q = Quat(Eigen::AngleAxisd(tilt, right)) * Quat(Eigen::AngleAxisd(roll, forward));
    next.orientation = (q * current.orientation).normalized();
  }
  return next;
}

}  // namespace acdr
