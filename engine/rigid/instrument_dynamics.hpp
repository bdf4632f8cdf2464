// The instrument's velocity update over one step: the rigid body driven by the virtual coupling
// (a spring and damper pulling its grip toward the device's target), the nucleus's reaction and
// gravity, solved implicitly in the six velocities so that any drag is stable. Pure functions:
// the caller hands the resulting force and torque to the rigid world, which integrates them
// together with the contacts.
#pragma once

#include "engine/core/types.hpp"
#include "engine/geometry/collider.hpp"
#include "engine/rigid/instrument_config.hpp"

namespace acdr {

/// The coupling's gains with its "critically damped" defaults resolved.
struct CouplingGains {
  double stiffness_N_m = 0.0;         ///< ks, grip translation
  double damping_Ns_m = 0.0;          ///< kd, grip translation
  double rot_stiffness_Nm_rad = 0.0;  ///< kr, orientation
  double rot_damping_Nms_rad = 0.0;   ///< krd, orientation
};

/// Gains of `config` for a body of mass `mass_kg` whose inertia across the shaft is
/// `inertia_perp_kg_m2`: a negative damping becomes the critical one, kd = 2 sqrt(m ks) and
/// krd = 2 sqrt(I kr).
CouplingGains coupling_gains(const CouplingConfig& config, double mass_kg,
                             double inertia_perp_kg_m2);

/// The rigid instrument at the start of a step, world frame.
struct InstrumentBodyState {
  double mass_kg = 0.0;
  Eigen::Matrix3d inertia_kg_m2 = Eigen::Matrix3d::Identity();  ///< about the centre of mass
  Vec3 com_m = Vec3::Zero();                                    ///< centre of mass
  Vec3 com_velocity_m_s = Vec3::Zero();                         ///< velocity of the centre of mass
  Vec3 angular_velocity_rad_s = Vec3::Zero();
  Pose grip;  ///< where the coupling holds the body
};

/// Where the coupling pulls the grip: the device's filtered pose and its velocities.
struct CouplingTarget {
  Pose pose;
  Vec3 velocity_m_s = Vec3::Zero();
  Vec3 angular_velocity_rad_s = Vec3::Zero();
};

/// The body's velocities after the step and the force and torque that produce them over dt.
struct InstrumentUpdate {
  Vec3 com_velocity_m_s = Vec3::Zero();
  Vec3 angular_velocity_rad_s = Vec3::Zero();
  Vec3 force_N = Vec3::Zero();    ///< on the centre of mass: m (v1 - v0) / dt
  Vec3 torque_Nm = Vec3::Zero();  ///< about the centre of mass: I (w1 - w0) / dt
};

/// One backward-Euler step in the generalised velocity u = (v, w) of the centre of mass
/// (Baraff & Witkin 1998, implicit in the damping):
///   (M + dt D) u1 = M u0 + dt (f + D_n u0),
/// with M = diag(m, I); f the coupling spring (at the current pose), the damper's target-velocity
/// part, the nucleus's reaction and gravity; D the coupling damper acting at the grip plus the
/// nucleus's drag acting at `reaction.reference_point`. The nucleus's force was evaluated at u0,
/// so its drag part D_n u0 is added back and taken at u1 instead: the update is stable for any
/// drag, however large.
InstrumentUpdate implicit_instrument_update(const InstrumentBodyState& body,
                                            const CouplingGains& gains,
                                            const CouplingTarget& target,
                                            const BodyReaction& reaction, const Vec3& gravity_m_s2,
                                            double dt_s);

/// The coupling's force on the grip (what the user's hand supplies, N): the spring and damper
/// between the target and the grip at `grip` moving at `grip_velocity_m_s`.
Vec3 coupling_force_N(const CouplingGains& gains, const CouplingTarget& target, const Pose& grip,
                      const Vec3& grip_velocity_m_s);

/// The bending moment a shaft along `shaft_axis` (unit) carries for a moment
/// `moment_about_grip_Nm` of its distal loads about the grip: the moment less its torsion
/// component along the axis, N m.
double shaft_bending_moment_Nm(const Vec3& moment_about_grip_Nm, const Vec3& shaft_axis);

/// Rotation vector taking orientation `from` to `to` the shortest way, rad.
Vec3 rotation_between(const Quat& from, const Quat& to);

}  // namespace acdr
