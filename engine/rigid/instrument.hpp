// The hand instrument's geometry and mass properties, derived once from its configuration.
// Body frame: origin at the grip G, shaft along local -z to the working tip T = (0,0,-L).
#pragma once

#include <vector>

#include "engine/geometry/collider.hpp"
#include "engine/rigid/instrument_config.hpp"

namespace acdr {

class InstrumentGeometry {
 public:
  explicit InstrumentGeometry(const InstrumentConfig& config);

  const InstrumentConfig& config() const { return config_; }
  /// Colliders in the body frame (pose relative to the grip), body index 0.
  const std::vector<Collider>& local_colliders() const { return local_colliders_; }
  /// Centre of mass in the body frame (m).
  const Vec3& center_of_mass() const { return com_; }
  /// Principal inertia about the centre of mass, body axes (kg·m^2).
  const Vec3& principal_inertia() const { return inertia_; }
  /// The working point (centre of the blade or cup) in the body frame.
  const Vec3& working_point() const { return working_point_; }
  double yield_moment_Nm() const { return config_.yield_moment_Nm(); }
  double warning_moment_Nm() const { return config_.warning_fraction * yield_moment_Nm(); }

  /// Colliders placed at a grip pose with the body's velocities (about the grip origin). A
  /// rongeur's jaws stand at `closure` (0 open .. 1 closed) and turn at `closure_rate` (1/s),
  /// which adds their hinge motion to their velocities; other shapes ignore both.
  void world_colliders(const Pose& grip, const Vec3& v_grip, const Vec3& omega,
                       std::vector<Collider>& out, double closure = 0.0,
                       double closure_rate_1_s = 0.0) const;

  // ---- Rongeur jaws (config().has_jaws()); colliders 0 and 1 are the jaws ----
  static constexpr int kJawCount = 2;
  /// Jaw k's plate (its collider's pose) in the body frame at a closure in [0, 1].
  Pose jaw_pose(int k, double closure) const;
  /// Jaw k's angular velocity about its hinge in the body frame at a closure rate (1/s).
  Vec3 jaw_angular_velocity(int k, double closure_rate_1_s) const;
  /// The hinge point (the shaft's tip) in the body frame.
  Vec3 hinge() const { return Vec3(0, 0, -config_.shaft_length_m); }
  /// Whether a body-frame point lies in the space between the jaws at this closure: inside
  /// both jaws' inner faces, within their width and length.
  bool between_jaws(const Vec3& body_p, double closure) const;

 private:
  InstrumentConfig config_;
  std::vector<Collider> local_colliders_;
  Vec3 com_ = Vec3::Zero();
  Vec3 inertia_ = Vec3::Zero();
  Vec3 working_point_ = Vec3::Zero();
};

}  // namespace acdr
