// Orbit camera.
#include "ui/orbit_camera.hpp"

#include <algorithm>
#include <cmath>

namespace acdr {
namespace {
constexpr float kMaxPitch = 1.48f;  // ~85 degrees: never straight down (up vector degenerates)
}

void OrbitCamera::reset(const RenderCamera& camera) {
  base_ = camera;
  target_ = camera.target;
  const Eigen::Vector3f d = camera.eye - camera.target;
  distance_ = std::max(d.norm(), 1e-4f);
  pitch_ = std::asin(std::clamp(d.z() / distance_, -1.0f, 1.0f));
  yaw_ = std::atan2(d.x(), -d.y());
}

void OrbitCamera::orbit(float dx_px, float dy_px, float rad_per_px) {
  yaw_ -= dx_px * rad_per_px;
  pitch_ = std::clamp(pitch_ + dy_px * rad_per_px, -kMaxPitch, kMaxPitch);
}

void OrbitCamera::set_angles(float yaw_rad, float pitch_rad) {
  yaw_ = yaw_rad;
  pitch_ = std::clamp(pitch_rad, -kMaxPitch, kMaxPitch);
}

void OrbitCamera::zoom(float notches) {
  distance_ = std::clamp(distance_ * std::pow(0.88f, notches), 0.005f, 2.0f);
}

void OrbitCamera::pan(float dx_px, float dy_px, float viewport_height_px) {
  const RenderCamera c = camera();
  const Eigen::Vector3f forward = (c.target - c.eye).normalized();
  const Eigen::Vector3f right = forward.cross(c.up).normalized();
  const Eigen::Vector3f up = right.cross(forward);
  // Metres per pixel at the target's depth.
  const float m_per_px = 2.0f * distance_ * std::tan(0.5f * c.fov_y_deg * 3.14159265f / 180.0f) /
                         std::max(viewport_height_px, 1.0f);
  target_ += (-dx_px * right + dy_px * up) * m_per_px;
}

RenderCamera OrbitCamera::camera() const {
  RenderCamera c = base_;
  const Eigen::Vector3f dir(std::cos(pitch_) * std::sin(yaw_), -std::cos(pitch_) * std::cos(yaw_),
                            std::sin(pitch_));
  c.target = target_;
  c.eye = target_ + distance_ * dir;
  c.up = Eigen::Vector3f::UnitZ();
  c.near_m = std::max(1e-4f, 0.02f * distance_);
  c.far_m = std::max(c.far_m, 20.0f * distance_);
  return c;
}

}  // namespace acdr
