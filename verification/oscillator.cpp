// oscillator: a particle on a spring to a fixed particle oscillates at omega = sqrt(k/m). The
// measured frequency (mean period between upward zero crossings, linearly interpolated) is
// compared with sqrt(k/m) / 2 pi. Viscosity and gravity are off by default: with them the
// motion is a damped oscillation at omega sqrt(1 - zeta^2), a different closed form.
// Backward Euler's phase error is about (omega dt)^2 / 3, so dt must resolve the period
// (omega dt <= 0.1 for 1 %); the default dt gives omega dt ~ 0.02.
#include <cmath>
#include <numbers>

#include "verification/cases.hpp"

namespace acdr::verification {

VerificationCaseSpec oscillator_defaults(bool fast) {
  VerificationCaseSpec s;
  add_material_parameters(s, 1.0e-5);
  s.set("viscosity_Pa_s", 0.0);
  s.set("gravity_m_s2", 0.0);
  s.params.push_back({"amplitude_m", 0.1e-3, "m", "initial stretch (below delta_max)"});
  s.params.push_back({"periods", fast ? 3.0 : 6.0, "1", "periods simulated"});
  s.params.push_back({"tolerance", 0.01, "1", "relative tolerance"});
  return s;
}

std::vector<VerificationRow> run_oscillator(const VerificationCaseSpec& spec) {
  const double h = spec.get("spacing_m");
  const double dt = spec.get("dt_s");
  const double k = spec.get("bond_stiffness_N_m");
  const double m = spec.get("density_kg_m3") * h * h * h;
  const double omega = std::sqrt(k / m);
  const double period = 2.0 * std::numbers::pi / omega;

  NucleusParticleSetup setup;
  setup.positions_m = {Vec3::Zero(), Vec3(h + spec.get("amplitude_m"), 0.0, 0.0)};
  setup.fixed = {1, 0};
  NucleusParticleSetup::Bond bond;
  bond.i = 0;
  bond.j = 1;
  bond.stiffness_N_m = k;
  bond.break_stretch_m = spec.get("bond_break_m");
  bond.rest_length_m = h;
  setup.bonds.push_back(bond);
  Nucleus nucleus(nucleus_config_from(spec), solver_config_from(spec), gravity_from(spec), {},
                  setup, NucleusOptions{});

  const int steps = static_cast<int>(std::ceil(spec.get("periods") * period / dt)) + 2;
  StepLog log;
  double prev = nucleus.positions()[1].x() - h;
  double first = -1.0, last = -1.0;
  int crossings = 0;
  for (int s = 1; s <= steps; ++s) {
    step_logged(nucleus, dt, {}, {}, log);
    const double u = nucleus.positions()[1].x() - h;
    if (prev < 0.0 && u >= 0.0) {  // upward zero crossing
      const double t = (s - 1 + (-prev) / (u - prev)) * dt;
      if (first < 0.0) first = t;
      last = t;
      ++crossings;
    }
    prev = u;
  }
  const double measured = crossings >= 2 ? (crossings - 1) / (last - first) : std::nan("");
  VerificationRow row = make_row(spec, "frequency (Hz)", measured, omega / (2.0 * std::numbers::pi),
                                 spec.get("tolerance"));
  if (!log.ok) fail_row(row, "numerical trouble in stage " + log.stage);
  if (nucleus.broken_bond_count() > 0) fail_row(row, "the spring broke: amplitude above delta_max");
  if (crossings < 2) fail_row(row, "fewer than two oscillations: motion overdamped or dt too large");
  return {row};
}

}  // namespace acdr::verification
