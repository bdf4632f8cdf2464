// lever_feedback (seed Eq. 6): the second scooping phase. The prism (length l, mass m_stick,
// centre of mass at l/2) rests on the box edge C and is levered about it: the hand pushes down
// at D, a distance d from C, and the far end A, at l - d beyond C, moves up through the
// nucleus, which shears it with F_s = mu A U / H (Eq. 3). In steady motion the moments about C
// balance (Eq. 6):
//   F_feedback d = (l/2 - d) m_stick g + (l - d) mu A U / H.
// The lever is simulated as a rigid body rotating about C, driven by a virtual coupling (spring
// and damper, as the haptic device drives the instrument) whose target turns at a constant
// rate; the nucleus acts on the tip through its reaction torque about C and drag coefficient,
// with the implicit update the World uses. The simulated feedback is the coupling force once
// the motion is steady; Eq. 6 is evaluated with the measured tip speed.
// Geometry of the shear: the tip is a plate of area A (normal y) moving vertically past a
// fixed wall at gap H, the layer periodic in x and z (an infinite plate, as Eq. 3 assumes);
// rotation is small over the run (< 3 degrees), so the plate is taken to translate. The layer
// is weightless: its weight would rest on the box floor, which a periodic layer has not.
#include <cmath>

#include "verification/cases.hpp"

namespace acdr::verification {

VerificationCaseSpec lever_feedback_defaults(bool fast) {
  VerificationCaseSpec s;
  add_material_parameters(s, 1.0e-3);
  s.params.push_back({"lever_length_m", 0.06, "m", "prism length l (D to A)"});
  s.params.push_back({"pivot_distance_m", 0.02, "m", "distance d from D to the pivot C"});
  s.params.push_back({"prism_mass_kg", 0.01, "kg", "prism mass m_stick"});
  s.params.push_back({"tip_area_length_m", 6.0e-3, "m", "sheared tip area, length"});
  s.params.push_back({"tip_area_height_m", 6.0e-3, "m", "sheared tip area, height"});
  s.params.push_back({"gap_m", 4.0e-3, "m", "nucleus gap H beside the tip"});
  s.params.push_back({"tip_speed_m_s", 0.01, "m/s", "commanded tip speed U"});
  s.params.push_back({"coupling_stiffness_N_m", 500.0, "N/m", "virtual coupling at D"});
  s.params.push_back({"duration_s", 0.0, "s",
                      "simulated time, averaged over its second half; 0: ten time constants of "
                      "the coupling against the shear, at least 0.12 s"});
  s.params.push_back({"tolerance", 0.05, "1", "relative tolerance"});
  return s;
}

std::vector<VerificationRow> run_lever_feedback(const VerificationCaseSpec& spec) {
  const double h = spec.get("spacing_m");
  const double dt = spec.get("dt_s");
  const double g = spec.get("gravity_m_s2");
  const double mu = spec.get("viscosity_Pa_s");
  const double l = spec.get("lever_length_m");
  const double d = spec.get("pivot_distance_m");
  const double m = spec.get("prism_mass_kg");
  const double arm = l - d;  // C to the tip
  const int nx = std::max(2, static_cast<int>(std::lround(spec.get("tip_area_length_m") / h)));
  const int nz = std::max(2, static_cast<int>(std::lround(spec.get("tip_area_height_m") / h)));
  const int ny = std::max(1, static_cast<int>(std::lround(spec.get("gap_m") / h)));
  const double Lx = nx * h, Lz = nz * h, H = ny * h;
  const double kc = spec.get("coupling_stiffness_N_m");

  // The sheared layer beside the tip: x in [arm - Lx/2, arm + Lx/2), z in [-Lz/2, Lz/2),
  // fixed wall at y = 0, the tip plate's face at y = H.
  NucleusParticleSetup setup;
  add_lattice(setup.positions_m, Vec3(arm - 0.5 * Lx + 0.5 * h, 0.5 * h, -0.5 * Lz + 0.5 * h), nx,
              ny, nz, h);
  NucleusOptions opt;
  opt.bonds_enabled = false;
  opt.periodic = {true, false, true};
  opt.periodic_min_m = Vec3(arm - 0.5 * Lx, 0.0, -0.5 * Lz);
  opt.periodic_max_m = Vec3(arm + 0.5 * Lx, 0.0, 0.5 * Lz);
  Collider wall;
  wall.kind = ColliderKind::kHalfSpace;  // solid below local z = 0; local z -> world +y
  wall.pose.orientation = Quat(Eigen::AngleAxisd(-0.5 * M_PI, Vec3::UnitX()));
  Collider plate;
  plate.kind = ColliderKind::kBox;
  plate.half_extents_m = Vec3(10.0 * Lx, h, 10.0 * Lz);
  plate.pose.position = Vec3(arm, H + h, 0.0);
  plate.body = 0;
  VerificationCaseSpec weightless = spec;
  weightless.set("gravity_m_s2", 0.0);
  Nucleus nucleus(nucleus_config_from(spec), solver_config_from(spec), gravity_from(weightless),
                  std::span<const Collider>(&wall, 1), setup, opt);

  // Lever about C (the origin): angle phi (tip up positive, a rotation about -y).
  const double inertia = m * (l * l / 12.0 + (0.5 * l - d) * (0.5 * l - d));
  const double bc = 2.0 * std::sqrt(inertia / (d * d) * kc);  // critically damped coupling
  const double omega_target = spec.get("tip_speed_m_s") / arm;
  double phi = 0.0, phidot = 0.0;
  BodyReaction reaction;
  reaction.reference_point = Vec3::Zero();
  StepLog log;
  // The lever approaches steady motion with the time constant of the coupling spring against
  // the shear drag, tau = (mu A / H) (l - d)^2 / (k_c d^2).
  double duration = spec.get("duration_s");
  if (duration <= 0.0) {
    const double tau = mu * Lx * Lz / H * arm * arm / (kc * d * d);
    duration = std::max(0.12, 10.0 * tau);
  }
  const int steps = std::max(4, static_cast<int>(std::lround(duration / dt)));
  // Run the estimated settling time, then windows until the mean feedback force changes by
  // less than 0.1 % between windows (the lagged nucleus torque converges more slowly when its
  // drag estimate is an over-bound, at large steps).
  const int window = std::max(20, steps / 4);
  double force_sum = 0.0, speed_sum = 0.0, previous = std::nan("");
  int count = 0;
  int s = 0;
  const int max_steps = steps + 60 * window;
  while (s < max_steps) {
    const double t = s * dt;
    plate.linear_velocity_m_s = Vec3(0.0, 0.0, phidot * arm);
    step_logged(nucleus, dt, std::span<const Collider>(&plate, 1),
                std::span<BodyReaction>(&reaction, 1), log);
    // Moments about C in the phi sense (about -y): nucleus, gravity, coupling at D.
    const double tau_n = -reaction.torque_Nm.y();
    const double tau_g = -(0.5 * l - d) * m * g;
    const double drag = reaction.rot_drag_Nms;
    const double z_target = -d * omega_target * (t + dt);  // D moves down as the tip rises
    const double v_target = -d * omega_target;
    // Backward Euler in phidot with the coupling spring and damper and the nucleus drag at the
    // new velocity: (I + dt (drag + d^2 b + dt d^2 k)) phidot1 = ...
    const double lhs = inertia + dt * (drag + d * d * bc + dt * d * d * kc);
    const double rhs = inertia * phidot +
                       dt * (tau_g + tau_n + drag * phidot - d * kc * (z_target + d * phi) -
                             d * bc * v_target);
    phidot = rhs / lhs;
    phi += dt * phidot;
    const double f_d = kc * (z_target + d * phi) + bc * (v_target + d * phidot);  // on D, +z
    ++s;
    if (s > steps - window) {
      force_sum += -f_d;  // the hand pushes D down with this force
      speed_sum += phidot * arm;
      ++count;
    }
    if (s >= steps && count == window) {
      const double mean = force_sum / count;
      if (std::abs(mean - previous) <= 1e-3 * std::abs(mean)) break;
      previous = mean;
      if (s < max_steps) {
        force_sum = speed_sum = 0.0;
        count = 0;
      }
    }
  }
  const double feedback = force_sum / count;
  const double U = speed_sum / count;
  const double A = Lx * Lz;
  const double analytic = ((0.5 * l - d) * m * g + arm * mu * A * U / H) / d;
  VerificationRow row =
      make_row(spec, "feedback force at D (N)", feedback, analytic, spec.get("tolerance"));
  if (!log.ok) fail_row(row, "numerical trouble in stage " + log.stage);
  return {row};
}

}  // namespace acdr::verification
