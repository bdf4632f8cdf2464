// Smooth device trajectories from a few waypoints, for demonstration attempts.
//
// Waypoint CSV (docs/trajectory-format.md): '#' comments, header
//   t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg[,grip][,instrument]
// (the optional grip, 0 open .. 1 closed, passes through to the trajectory's grip column and
// is interpolated along the same minimum-jerk profile; the optional instrument passes through
// to the trajectory's instrument column, asked for from its waypoint on).
// Consecutive waypoints are joined by minimum-jerk segments (Flash & Hogan 1985: the
// smoothest point-to-point hand motion, s(u) = 10u^3 - 15u^4 + 6u^5), in position and in
// orientation (slerp along s), so the hand starts and stops each segment at rest.
#pragma once

#include <optional>
#include <string>

#include "engine/devices/trajectory.hpp"

namespace acdr {

/// Parses waypoint CSV text. Errors as "name:line: what (got X, expected Y)".
std::optional<Trajectory> parse_waypoints(const std::string& text, const std::string& name,
                                          std::string* error);

/// Samples the minimum-jerk path through the waypoints at `rate_hz`.
Trajectory sample_waypoints(const Trajectory& waypoints, double rate_hz);

/// Orientation from roll (x), pitch (y), yaw (z) in degrees, applied in z-y-x order.
Quat quat_from_rpy_deg(double roll, double pitch, double yaw);

}  // namespace acdr
