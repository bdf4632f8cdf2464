// The instrument's implicit velocity update against closed forms: free fall, a critically
// damped coupling, drag decay (translational and rotational), stability under huge drag, a
// moving target tracked without lag; the shaft's bending moment and the coupling's gains.
// The body is stepped as the rigid world integrates it: semi-implicit Euler, x1 = x0 + dt v1.
#include "engine/rigid/instrument_dynamics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace acdr {
namespace {

constexpr double kMass = 0.03;     // kg, the default instrument
constexpr double kInertia = 2e-5;  // kg m^2, about every axis
constexpr double kDt = 1e-3;       // s

/// A body at rest at `at` whose grip is its centre of mass (so translation and rotation
/// decouple), with an isotropic inertia.
InstrumentBodyState body_at(const Vec3& at) {
  InstrumentBodyState b;
  b.mass_kg = kMass;
  b.inertia_kg_m2 = kInertia * Eigen::Matrix3d::Identity();
  b.com_m = at;
  b.grip.position = at;
  return b;
}

/// Takes the update's velocities and moves the centre of mass (and grip) by dt v1.
void advance(InstrumentBodyState& b, const InstrumentUpdate& u, double dt) {
  b.com_velocity_m_s = u.com_velocity_m_s;
  b.angular_velocity_rad_s = u.angular_velocity_rad_s;
  b.com_m += dt * u.com_velocity_m_s;
  b.grip.position = b.com_m;
}

/// A target at rest at `at`.
CouplingTarget target_at(const Vec3& at) {
  CouplingTarget t;
  t.pose.position = at;
  return t;
}

const Vec3 kNoGravity = Vec3::Zero();

TEST(InstrumentDynamics, FreeFallWithoutCouplingIsExactInVelocity) {
  // Only gravity: each step adds g dt to the velocity exactly, and the generalised force is the
  // weight. Semi-implicit Euler puts the position g dt t / 2 below x0 + g t^2 / 2.
  const Vec3 g(0, 0, -9.81);
  InstrumentBodyState b = body_at(Vec3(0, 0, 0.1));
  const CouplingGains none;
  const int n = 100;
  for (int k = 0; k < n; ++k) {
    const InstrumentUpdate u =
        implicit_instrument_update(b, none, target_at(Vec3::Zero()), BodyReaction{}, g, kDt);
    EXPECT_NEAR((u.force_N - kMass * g).norm(), 0.0, 1e-12 * kMass * g.norm());
    EXPECT_NEAR(u.torque_Nm.norm(), 0.0, 1e-15);
    advance(b, u, kDt);
  }
  const double t = n * kDt;
  EXPECT_NEAR(b.com_velocity_m_s.z(), g.z() * t, 1e-12);
  const double analytic = 0.1 + 0.5 * g.z() * t * t;
  const double fall = 0.5 * g.norm() * t * t;
  const double rel = std::abs(b.com_m.z() - analytic) / fall;
  std::printf(
      "free fall %.0f ms at dt %.0f ms: z %.6f m, closed form %.6f m, error %.2f %% of "
      "the fall (expected dt/t = %.2f %%; tolerance 1.5 %%)\n",
      1e3 * t, 1e3 * kDt, b.com_m.z(), analytic, 100 * rel, 100 * kDt / t);
  EXPECT_LT(rel, 0.015);
  EXPECT_NEAR(b.com_m.z() - analytic, 0.5 * g.z() * kDt * t, 1e-12);
  EXPECT_DOUBLE_EQ(b.com_m.x(), 0.0);
}

/// Largest distance from the closed form x0 (1 + w t) e^(-w t) of a critically damped return,
/// as a fraction of x0, and the largest overshoot past the target, over 0.1 s at step dt.
struct CriticalRun {
  double max_error = 0.0;
  double overshoot = 0.0;
};
CriticalRun critically_damped_return(double dt) {
  CouplingConfig config;  // 500 N/m, damping < 0: critical
  const CouplingGains gains = coupling_gains(config, kMass, kInertia);
  const double x0 = 5e-3;
  const double omega = std::sqrt(gains.stiffness_N_m / kMass);
  InstrumentBodyState b = body_at(Vec3(x0, 0, 0));
  CriticalRun run;
  const int n = static_cast<int>(std::lround(0.1 / dt));
  for (int k = 1; k <= n; ++k) {
    advance(b,
            implicit_instrument_update(b, gains, target_at(Vec3::Zero()), BodyReaction{},
                                       kNoGravity, dt),
            dt);
    const double t = k * dt;
    const double analytic = x0 * (1.0 + omega * t) * std::exp(-omega * t);
    run.max_error = std::max(run.max_error, std::abs(b.com_m.x() - analytic) / x0);
    run.overshoot = std::max(run.overshoot, -b.com_m.x() / x0);
  }
  return run;
}

TEST(InstrumentDynamics, CriticallyDampedCouplingReturnsToItsTargetAsTheClosedForm) {
  // Default coupling on the default mass (w = sqrt(ks/m) = 129 rad/s), released 5 mm from its
  // target: x(t) = x0 (1 + w t) e^(-w t). The scheme is first order: halving dt halves the error.
  const CriticalRun coarse = critically_damped_return(kDt);
  const CriticalRun fine = critically_damped_return(0.5 * kDt);
  std::printf(
      "critically damped return: max error %.3f %% of x0 at dt 1 ms (tolerance 2 %%), "
      "%.3f %% at 0.5 ms (ratio %.2f, first order 0.5); overshoot %.4f %% of x0 "
      "(tolerance 0.1 %%)\n",
      100 * coarse.max_error, 100 * fine.max_error, fine.max_error / coarse.max_error,
      100 * coarse.overshoot);
  EXPECT_LT(coarse.max_error, 0.02);
  EXPECT_NEAR(fine.max_error / coarse.max_error, 0.5, 0.1);
  EXPECT_LT(coarse.overshoot, 1e-3);
}

TEST(InstrumentDynamics, DragDecaysTheVelocityAsBackwardEuler) {
  // The nucleus's drag alone, its force evaluated at the old velocity as the nucleus reports
  // it: v_n = v0 / (1 + dt c/m)^n exactly, and v0 e^(-c t / m) to first order in dt.
  const double c = 1.5;  // N s/m: c/m = 50 /s, time constant 20 ms
  const double v0 = 0.2;
  InstrumentBodyState b = body_at(Vec3::Zero());
  b.com_velocity_m_s = Vec3(v0, 0, 0);
  const int n = 20;
  for (int k = 0; k < n; ++k) {
    BodyReaction r;
    r.reference_point = b.com_m;
    r.drag_Ns_m = c;
    r.force_N = -c * b.com_velocity_m_s;
    advance(b,
            implicit_instrument_update(b, CouplingGains{}, target_at(b.com_m), r, kNoGravity, kDt),
            kDt);
  }
  const double discrete = v0 / std::pow(1.0 + kDt * c / kMass, n);
  const double analytic = v0 * std::exp(-c * n * kDt / kMass);
  const double rel = std::abs(b.com_velocity_m_s.x() - analytic) / analytic;
  std::printf(
      "drag decay over one time constant: v %.6f m/s, backward Euler %.6f, closed form "
      "%.6f, error %.2f %% (tolerance 3 %%)\n",
      b.com_velocity_m_s.x(), discrete, analytic, 100 * rel);
  EXPECT_NEAR(b.com_velocity_m_s.x(), discrete, 1e-12 * v0);
  EXPECT_LT(rel, 0.03);
}

TEST(InstrumentDynamics, RotationalDragDecaysTheSpinAsBackwardEuler) {
  const double c = 1e-3;  // N m s/rad: c/I = 50 /s
  const double w0 = 3.0;
  InstrumentBodyState b = body_at(Vec3::Zero());
  b.angular_velocity_rad_s = Vec3(0, w0, 0);
  const int n = 20;
  for (int k = 0; k < n; ++k) {
    BodyReaction r;
    r.reference_point = b.com_m;
    r.rot_drag_Nms = c;
    r.torque_Nm = -c * b.angular_velocity_rad_s;
    advance(b,
            implicit_instrument_update(b, CouplingGains{}, target_at(b.com_m), r, kNoGravity, kDt),
            kDt);
  }
  const double discrete = w0 / std::pow(1.0 + kDt * c / kInertia, n);
  const double analytic = w0 * std::exp(-c * n * kDt / kInertia);
  const double rel = std::abs(b.angular_velocity_rad_s.y() - analytic) / analytic;
  std::printf(
      "rotational drag decay over one time constant: w %.6f rad/s, closed form %.6f, "
      "error %.2f %% (tolerance 3 %%)\n",
      b.angular_velocity_rad_s.y(), analytic, 100 * rel);
  EXPECT_NEAR(b.angular_velocity_rad_s.y(), discrete, 1e-12 * w0);
  EXPECT_LT(rel, 0.03);
  EXPECT_NEAR(b.com_velocity_m_s.norm(), 0.0, 1e-15);
}

TEST(InstrumentDynamics, HugeDragNeverOvershoots) {
  // dt c / m = 3.3e4: an explicit update would reverse the velocity 3.3e4-fold each step. The
  // implicit one slows a moving body without reversing it.
  InstrumentBodyState moving = body_at(Vec3::Zero());
  moving.com_velocity_m_s = Vec3(0.5, 0, 0);
  BodyReaction r;
  r.reference_point = moving.com_m;
  r.drag_Ns_m = 1e6;
  r.force_N = -r.drag_Ns_m * moving.com_velocity_m_s;
  const InstrumentUpdate u = implicit_instrument_update(
      moving, CouplingGains{}, target_at(moving.com_m), r, kNoGravity, kDt);
  EXPECT_GT(u.com_velocity_m_s.x(), 0.0);
  EXPECT_NEAR(u.com_velocity_m_s.x(), 0.5 / (1.0 + kDt * r.drag_Ns_m / kMass), 1e-15);

  // A coupled body in drag c = 1000 N s/m (dt c / m = 33, explicitly unstable) creeps toward its
  // target without passing it, at the overdamped rate: x = x0 e^(-ks t / (c + kd)).
  const double c = 1e3;
  const CouplingGains gains = coupling_gains(CouplingConfig{}, kMass, kInertia);
  const double x0 = 5e-3;
  InstrumentBodyState b = body_at(Vec3(x0, 0, 0));
  double previous = b.com_m.x();
  const int n = 2000;
  for (int k = 0; k < n; ++k) {
    BodyReaction drag;
    drag.reference_point = b.com_m;
    drag.drag_Ns_m = c;
    drag.force_N = -c * b.com_velocity_m_s;
    advance(b, implicit_instrument_update(b, gains, target_at(Vec3::Zero()), drag, kNoGravity, kDt),
            kDt);
    ASSERT_TRUE(b.com_m.allFinite());
    ASSERT_GT(b.com_m.x(), 0.0) << "passed the target at step " << k;
    ASSERT_LE(b.com_m.x(), previous) << "moved away from the target at step " << k;
    previous = b.com_m.x();
  }
  const double t = n * kDt;
  const double creep = x0 * std::exp(-gains.stiffness_N_m * t / (c + gains.damping_Ns_m));
  const double rel = std::abs(b.com_m.x() - creep) / creep;
  std::printf(
      "drag %.0f N s/m (dt c/m = %.0f): after %.0f s %.4f mm from the target, "
      "overdamped closed form %.4f mm, error %.3f %% (tolerance 0.5 %%)\n",
      c, kDt * c / kMass, t, 1e3 * b.com_m.x(), 1e3 * creep, 100 * rel);
  EXPECT_LT(rel, 5e-3);
}

TEST(InstrumentDynamics, MovingTargetIsTrackedWithoutLag) {
  // The damper acts on the velocity relative to the target's, so a target moving at constant
  // velocity V is followed at V with the lag decaying to zero (no steady-state error).
  const CouplingGains gains = coupling_gains(CouplingConfig{}, kMass, kInertia);
  const Vec3 V(0.05, -0.02, 0.01);
  InstrumentBodyState b = body_at(Vec3::Zero());
  double lag = 0.0;
  for (int k = 0; k < 300; ++k) {
    CouplingTarget target = target_at(V * (k * kDt));
    target.velocity_m_s = V;
    advance(b, implicit_instrument_update(b, gains, target, BodyReaction{}, kNoGravity, kDt), kDt);
    lag = (V * ((k + 1) * kDt) - b.com_m).norm();
  }
  std::printf("moving target at %.3f m/s: lag after 0.3 s %.3g m, velocity error %.3g m/s\n",
              V.norm(), lag, (b.com_velocity_m_s - V).norm());
  EXPECT_LT(lag, 1e-9);
  EXPECT_LT((b.com_velocity_m_s - V).norm(), 1e-8);
}

TEST(InstrumentDynamics, CouplingAtAnOffsetGripTurnsTheBody) {
  // A spring pulling a grip 40 mm above the centre of mass sideways: the generalised torque is
  // r x F, so the body starts to turn about y; with no damping the first step's torque is exact.
  CouplingGains gains;
  gains.stiffness_N_m = 500.0;
  InstrumentBodyState b = body_at(Vec3::Zero());
  b.grip.position = Vec3(0, 0, 0.04);
  const InstrumentUpdate u = implicit_instrument_update(b, gains, target_at(Vec3(1e-3, 0, 0.04)),
                                                        BodyReaction{}, kNoGravity, kDt);
  const Vec3 spring(0.5, 0, 0);  // 500 N/m * 1 mm
  EXPECT_NEAR((u.force_N - spring).norm(), 0.0, 1e-12);
  EXPECT_NEAR((u.torque_Nm - Vec3(0, 0, 0.04).cross(spring)).norm(), 0.0, 1e-12);
  EXPECT_GT(u.angular_velocity_rad_s.y(), 0.0);
}

TEST(InstrumentDynamics, CouplingForceIsSpringAndDamperAtTheGrip) {
  CouplingGains gains;
  gains.stiffness_N_m = 400.0;
  gains.damping_Ns_m = 3.0;
  CouplingTarget target = target_at(Vec3(0.01, 0, 0));
  target.velocity_m_s = Vec3(0, 0.1, 0);
  Pose grip;
  grip.position = Vec3(0.008, 0, 0);
  const Vec3 f = coupling_force_N(gains, target, grip, Vec3(0, 0.05, 0));
  EXPECT_NEAR((f - Vec3(0.8, 0.15, 0)).norm(), 0.0, 1e-12);
}

TEST(InstrumentDynamics, CriticalDampingResolvesFromMassAndInertia) {
  CouplingConfig config;
  config.stiffness_N_m = 500.0;
  config.rot_stiffness_Nm_rad = 0.5;
  const CouplingGains critical = coupling_gains(config, 0.03, 2e-5);
  EXPECT_DOUBLE_EQ(critical.damping_Ns_m, 2.0 * std::sqrt(0.03 * 500.0));
  EXPECT_DOUBLE_EQ(critical.rot_damping_Nms_rad, 2.0 * std::sqrt(2e-5 * 0.5));
  config.damping_Ns_m = 1.25;
  config.rot_damping_Nms_rad = 0.0;  // zero is a given damping, not "critical"
  const CouplingGains given = coupling_gains(config, 0.03, 2e-5);
  EXPECT_EQ(given.damping_Ns_m, 1.25);
  EXPECT_EQ(given.rot_damping_Nms_rad, 0.0);
}

TEST(InstrumentDynamics, ShaftBendingMomentLeavesOutTorsion) {
  const Vec3 axis = Vec3(1, 1, 0).normalized();
  EXPECT_NEAR(shaft_bending_moment_Nm(0.7 * axis, axis), 0.0, 1e-15);
  EXPECT_NEAR(shaft_bending_moment_Nm(Vec3(0, 0, 0.3), axis), 0.3, 1e-15);
  // 3-4-12 along z: the bending part is the (3, 4) across the shaft.
  EXPECT_NEAR(shaft_bending_moment_Nm(Vec3(3, 4, 12), Vec3::UnitZ()), 5.0, 1e-12);
}

TEST(InstrumentDynamics, RotationBetweenTakesTheShortWay) {
  const Quat a(Eigen::AngleAxisd(0.3, Vec3::UnitZ()));
  const Quat b(Eigen::AngleAxisd(0.5, Vec3::UnitZ()));
  EXPECT_NEAR((rotation_between(a, b) - Vec3(0, 0, 0.2)).norm(), 0.0, 1e-12);
  // 350 degrees one way is 10 degrees the other.
  const Quat c(Eigen::AngleAxisd(350.0 * M_PI / 180.0, Vec3::UnitX()));
  EXPECT_NEAR((rotation_between(Quat::Identity(), c) - Vec3(-10.0 * M_PI / 180.0, 0, 0)).norm(),
              0.0, 1e-12);
}

}  // namespace
}  // namespace acdr
