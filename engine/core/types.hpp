// Basic geometric types of the engine. SI units everywhere: metres, kilograms, seconds, newtons.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace acdr {

using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;

/// A rigid pose: position (m) and orientation (unit quaternion).
struct Pose {
  Vec3 position = Vec3::Zero();
  Quat orientation = Quat::Identity();

  Vec3 apply(const Vec3& local) const { return position + orientation * local; }
  Vec3 inverse_apply(const Vec3& world) const {
    return orientation.conjugate() * (world - position);
  }
};

/// Standard gravity (m/s^2), the default of every scenario.
inline constexpr double kStandardGravity = 9.80665;

}  // namespace acdr
