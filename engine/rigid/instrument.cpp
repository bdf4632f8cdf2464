// Instrument geometry: the seed's rectangular prism (a flat blade at the end of a round shaft)
// or a cup curette (a hemispherical cup at the end of the shaft, opening sideways or angled back).
#include "engine/rigid/instrument.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace acdr {

InstrumentGeometry::InstrumentGeometry(const InstrumentConfig& config) : config_(config) {
  const double L = config.shaft_length_m;
  const double r = 0.5 * config.shaft_diameter_m;

  // Shaft: a capsule from the grip to the tip.
  Collider shaft;
  shaft.kind = ColliderKind::kCapsule;
  shaft.pose.position = Vec3(0, 0, -0.5 * L);
  shaft.radius_m = r;
  shaft.half_length_m = 0.5 * L;
  shaft.body = 0;

  Collider head;
  head.body = 0;
  if (config.has_jaws()) {
    // Two jaw plates at the tip, placed open; world_colliders turns them to the closure.
    Collider jaw;
    jaw.body = 0;
    jaw.kind = ColliderKind::kBox;
    jaw.half_extents_m =
        Vec3(0.5 * config.jaw_wall_m, 0.5 * config.jaw_width_m, 0.5 * config.jaw_length_m);
    local_colliders_.clear();
    for (int k = 0; k < kJawCount; ++k) {
      jaw.pose = jaw_pose(k, 0.0);
      local_colliders_.push_back(jaw);
    }
    local_colliders_.push_back(shaft);
    // The middle of the jaws along their axis, bent off the shaft's by jaw_angle.
    working_point_ = hinge() + 0.5 * config.jaw_length_m *
                                   Vec3(std::sin(config.jaw_angle_rad), 0.0,
                                        -std::cos(config.jaw_angle_rad));
  } else if (config.shape == InstrumentShape::kPrism) {
    // Blade hangs below the tip: its upper face at the tip, centred on the shaft axis.
    head.kind = ColliderKind::kBox;
    head.half_extents_m = 0.5 * config.blade_size_m;
    head.pose.position = Vec3(0, 0, -L - 0.5 * config.blade_size_m.z());
    working_point_ = head.pose.position;
  } else {
    // Hemispherical cup hanging below the shaft end, its sphere touching the end. The opening
    // (the shell's local +z) is turned about body y to make the configured angle with the
    // shaft's tip direction (-z): a turn of pi - angle takes +z to (sin a, 0, -cos a), so the
    // default pi/2 opens toward body +x and larger angles lean the opening back toward the grip.
    head.kind = ColliderKind::kCupShell;
    head.radius_m = 0.5 * config.cup_diameter_m + config.cup_wall_m;
    head.thickness_m = config.cup_wall_m;
    head.pose.position = Vec3(0, 0, -L - head.radius_m);
    head.pose.orientation =
        Quat(Eigen::AngleAxisd(std::numbers::pi - config.cup_opening_angle_rad, Vec3::UnitY()));
    working_point_ = head.pose.position;
  }
  if (!config.has_jaws()) local_colliders_ = {head, shaft};

  // Mass: treated as a uniform rod from grip to tip (the handle above the grip is held by the
  // hand and not simulated); inertia of a slender rod about its centre.
  const double m = config.mass_kg;
  com_ = Vec3(0, 0, -0.5 * L);
  const double i_perp = m * L * L / 12.0 + m * r * r / 4.0;
  const double i_axial = 0.5 * m * r * r;
  inertia_ = Vec3(i_perp, i_perp, i_axial);
}

void InstrumentGeometry::world_colliders(const Pose& grip, const Vec3& v_grip, const Vec3& omega,
                                         std::vector<Collider>& out, double closure,
                                         double closure_rate_1_s) const {
  out.resize(local_colliders_.size());
  for (std::size_t i = 0; i < local_colliders_.size(); ++i) {
    Collider c = local_colliders_[i];
    c.pose.position = grip.apply(local_colliders_[i].pose.position);
    c.pose.orientation = grip.orientation * local_colliders_[i].pose.orientation;
    c.linear_velocity_m_s = v_grip + omega.cross(c.pose.position - grip.position);
    c.angular_velocity_rad_s = omega;
    out[i] = c;
  }
  if (!config_.has_jaws()) return;
  // The jaws at the closure, turning about the hinge on top of the body's motion.
  const Vec3 hinge_w = grip.apply(hinge());
  for (int k = 0; k < kJawCount; ++k) {
    const Pose local = jaw_pose(k, closure);
    Collider& c = out[k];
    c.pose.position = grip.apply(local.position);
    c.pose.orientation = grip.orientation * local.orientation;
    const Vec3 w_jaw = grip.orientation * jaw_angular_velocity(k, closure_rate_1_s);
    c.linear_velocity_m_s = v_grip + omega.cross(c.pose.position - grip.position) +
                            w_jaw.cross(c.pose.position - hinge_w);
    c.angular_velocity_rad_s = omega + w_jaw;
  }
}

// Jaw k (sign s = +1 for the jaw on the +x side, -1 for the other) turns about body y at the
// hinge by b + s * a, b the jaws' bend (jaw_angle) and a half the opening times (1 - closure);
// a turn of -a about y takes the jaw's direction (0, 0, -1) to (sin a, 0, -cos a), so the +x
// jaw opens toward +x and a positive bend leans both toward +x. Its plate's inner face stands
// at s * depth in the jaw's own frame. Straight jaws (b = 0) turn by s * a alone.
Pose InstrumentGeometry::jaw_pose(int k, double closure) const {
  const double s = k == 0 ? 1.0 : -1.0;
  const double a = 0.5 * config_.jaw_opening_rad * (1.0 - std::clamp(closure, 0.0, 1.0));
  const Quat turn(Eigen::AngleAxisd(-s * a - config_.jaw_angle_rad, Vec3::UnitY()));
  const Vec3 centre(s * (config_.jaw_depth_m + 0.5 * config_.jaw_wall_m), 0.0,
                    -0.5 * config_.jaw_length_m);
  return Pose{hinge() + turn * centre, turn};
}

// d(angle)/dt = -s * (-half opening) * closure rate about y: closing turns each jaw toward
// the axis.
Vec3 InstrumentGeometry::jaw_angular_velocity(int k, double closure_rate_1_s) const {
  const double s = k == 0 ? 1.0 : -1.0;
  return Vec3(0.0, s * 0.5 * config_.jaw_opening_rad * closure_rate_1_s, 0.0);
}

bool InstrumentGeometry::between_jaws(const Vec3& body_p, double closure) const {
  if (!config_.has_jaws()) return false;
  for (int k = 0; k < kJawCount; ++k) {
    const double s = k == 0 ? 1.0 : -1.0;
    const Pose jaw = jaw_pose(k, closure);
    // In the jaw's frame with the hinge at the origin.
    const Vec3 q = jaw.orientation.conjugate() * (body_p - hinge());
    if (s * q.x() > config_.jaw_depth_m) return false;  // beyond the inner face
    if (std::abs(q.y()) > 0.5 * config_.jaw_width_m) return false;
    if (q.z() > 0.0 || q.z() < -config_.jaw_length_m) return false;
  }
  return true;
}

}  // namespace acdr
