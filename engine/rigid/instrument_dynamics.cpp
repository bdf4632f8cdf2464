// The instrument's implicit velocity update (see the header for the equation).
#include "engine/rigid/instrument_dynamics.hpp"

#include <cmath>

namespace acdr {
namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Jacobian = Eigen::Matrix<double, 3, 6>;

/// The cross-product matrix: skew(r) * a = r x a.
Eigen::Matrix3d skew(const Vec3& r) {
  Eigen::Matrix3d m;
  m << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
  return m;
}

/// Velocity of the point at offset r from the centre of mass: J u = v + w x r = v - r x w.
Jacobian point_jacobian(const Vec3& r) {
  Jacobian j;
  j << Eigen::Matrix3d::Identity(), -skew(r);
  return j;
}

}  // namespace

CouplingGains coupling_gains(const CouplingConfig& config, double mass_kg,
                             double inertia_perp_kg_m2) {
  CouplingGains g;
  g.stiffness_N_m = config.stiffness_N_m;
  g.damping_Ns_m =
      config.damping_Ns_m >= 0 ? config.damping_Ns_m : 2.0 * std::sqrt(mass_kg * g.stiffness_N_m);
  g.rot_stiffness_Nm_rad = config.rot_stiffness_Nm_rad;
  g.rot_damping_Nms_rad = config.rot_damping_Nms_rad >= 0
                              ? config.rot_damping_Nms_rad
                              : 2.0 * std::sqrt(inertia_perp_kg_m2 * g.rot_stiffness_Nm_rad);
  return g;
}

InstrumentUpdate implicit_instrument_update(const InstrumentBodyState& body,
                                            const CouplingGains& gains,
                                            const CouplingTarget& target,
                                            const BodyReaction& reaction, const Vec3& gravity_m_s2,
                                            double dt_s) {
  const double m = body.mass_kg;
  const double ks = gains.stiffness_N_m;
  const double kd = gains.damping_Ns_m;
  const double kr = gains.rot_stiffness_Nm_rad;
  const double krd = gains.rot_damping_Nms_rad;
  const Pose& grip = body.grip;
  const Vec3& com = body.com_m;

  // The coupling acts at the grip, the nucleus's drag at its reference point; rotational
  // damping and drag act on the angular velocity alone (P_w picks it out of u).
  const Vec3 r_g = grip.position - com;
  const Jacobian J_g = point_jacobian(r_g);
  const Jacobian J_w = point_jacobian(reaction.reference_point - com);
  Mat6 M = Mat6::Zero();
  M.topLeftCorner<3, 3>() = m * Eigen::Matrix3d::Identity();
  M.bottomRightCorner<3, 3>() = body.inertia_kg_m2;
  Mat6 P_w = Mat6::Zero();
  P_w.bottomRightCorner<3, 3>() = Eigen::Matrix3d::Identity();

  Vec6 u0;
  u0 << body.com_velocity_m_s, body.angular_velocity_rad_s;

  // Explicit loads: the coupling's springs at the current pose, the nucleus's reaction moved to
  // the centre of mass, gravity, and the dampers' pull toward the target's velocities.
  const Vec3 f_spring = ks * (target.pose.position - grip.position);
  const Vec3 t_spring = kr * rotation_between(grip.orientation, target.pose.orientation);
  Vec6 f = Vec6::Zero();
  f.head<3>() += f_spring + reaction.force_N + m * gravity_m_s2;
  f.tail<3>() += r_g.cross(f_spring) + t_spring + reaction.torque_Nm +
                 (reaction.reference_point - com).cross(reaction.force_N);
  f += J_g.transpose() * (kd * target.velocity_m_s);
  f.tail<3>() += krd * target.angular_velocity_rad_s;

  // Damping taken at the new velocity.
  const Mat6 D = kd * J_g.transpose() * J_g + krd * P_w +
                 reaction.drag_Ns_m * J_w.transpose() * J_w + reaction.rot_drag_Nms * P_w;
  // The nucleus's force was evaluated at u0: its drag part is moved to the new velocity.
  const Vec6 rhs =
      M * u0 +
      dt_s * (f + (reaction.drag_Ns_m * J_w.transpose() * J_w + reaction.rot_drag_Nms * P_w) * u0);
  const Vec6 u1 = (M + dt_s * D).ldlt().solve(rhs);
  const Vec6 generalised = M * (u1 - u0) / dt_s;

  InstrumentUpdate out;
  out.com_velocity_m_s = u1.head<3>();
  out.angular_velocity_rad_s = u1.tail<3>();
  out.force_N = generalised.head<3>();
  out.torque_Nm = generalised.tail<3>();
  return out;
}

Vec3 coupling_force_N(const CouplingGains& gains, const CouplingTarget& target, const Pose& grip,
                      const Vec3& grip_velocity_m_s) {
  return gains.stiffness_N_m * (target.pose.position - grip.position) +
         gains.damping_Ns_m * (target.velocity_m_s - grip_velocity_m_s);
}

double shaft_bending_moment_Nm(const Vec3& moment_about_grip_Nm, const Vec3& shaft_axis) {
  Vec3 bending = moment_about_grip_Nm;
  bending -= bending.dot(shaft_axis) * shaft_axis;
  return bending.norm();
}

Vec3 rotation_between(const Quat& from, const Quat& to) {
  Quat d = to * from.conjugate();
  if (d.w() < 0) d.coeffs() *= -1.0;  // the shorter of the two rotations
  const Eigen::AngleAxisd aa(d);
  return aa.axis() * aa.angle();
}

}  // namespace acdr
