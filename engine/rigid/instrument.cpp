// Instrument geometry: the seed's rectangular prism (a flat blade at the end of a round shaft)
// or a cup curette (a hemispherical cup at the end of the shaft, opening sideways or angled back).
#include "engine/rigid/instrument.hpp"

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
  if (config.shape == InstrumentShape::kPrism) {
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
  local_colliders_ = {head, shaft};

  // Mass: treated as a uniform rod from grip to tip (the handle above the grip is held by the
  // hand and not simulated); inertia of a slender rod about its centre.
  const double m = config.mass_kg;
  com_ = Vec3(0, 0, -0.5 * L);
  const double i_perp = m * L * L / 12.0 + m * r * r / 4.0;
  const double i_axial = 0.5 * m * r * r;
  inertia_ = Vec3(i_perp, i_perp, i_axial);
}

void InstrumentGeometry::world_colliders(const Pose& grip, const Vec3& v_grip, const Vec3& omega,
                                         std::vector<Collider>& out) const {
  out.resize(local_colliders_.size());
  for (std::size_t i = 0; i < local_colliders_.size(); ++i) {
    Collider c = local_colliders_[i];
    c.pose.position = grip.apply(local_colliders_[i].pose.position);
    c.pose.orientation = grip.orientation * local_colliders_[i].pose.orientation;
    c.linear_velocity_m_s = v_grip + omega.cross(c.pose.position - grip.position);
    c.angular_velocity_rad_s = omega;
    out[i] = c;
  }
}

}  // namespace acdr
