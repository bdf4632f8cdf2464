// bond_break (seed Eq. 9-10): a bond, and a chain of bonds, pulled by a slowly increasing
// force break when the force reaches P_min = k delta_max. One end is fixed; the other is pulled
// by F(t) = P_ramp t / T. The load is quasi-static: the viscous lag c * (dF/dt) / k is kept
// below 0.5 % of P by the default ramp time.
#include <cmath>

#include "verification/cases.hpp"

namespace acdr::verification {

VerificationCaseSpec bond_break_defaults(bool fast) {
  VerificationCaseSpec s;
  add_material_parameters(s, 1.0e-3);
  s.set("gravity_m_s2", 0.0);
  s.params.push_back({"ramp_time_s", 20.0, "s", "time for the pull to reach 1.2 k delta_max"});
  s.params.push_back({"chain_bonds", fast ? 5.0 : 10.0, "1", "bonds in the chain"});
  s.params.push_back({"tolerance", 0.01, "1", "relative tolerance"});
  return s;
}

namespace {

/// Pulls the last particle of a straight chain of `bonds` bonds along +x; returns the pull at
/// the first break (NaN if none broke).
double pull_until_break(const VerificationCaseSpec& spec, int bonds, StepLog& log) {
  const double h = spec.get("spacing_m");
  const double dt = spec.get("dt_s");
  const double P = spec.get("bond_stiffness_N_m") * spec.get("bond_break_m");
  NucleusParticleSetup setup;
  for (int i = 0; i <= bonds; ++i) {
    setup.positions_m.push_back(Vec3(i * h, 0.0, 0.0));
    setup.fixed.push_back(i == 0 ? 1 : 0);
  }
  for (int i = 0; i < bonds; ++i) {
    NucleusParticleSetup::Bond b;
    b.i = i;
    b.j = i + 1;
    b.stiffness_N_m = spec.get("bond_stiffness_N_m");
    b.break_stretch_m = spec.get("bond_break_m");
    setup.bonds.push_back(b);
  }
  Nucleus nucleus(nucleus_config_from(spec), solver_config_from(spec), gravity_from(spec), {},
                  setup, NucleusOptions{});
  const double T = spec.get("ramp_time_s");
  const int steps = static_cast<int>(std::ceil(T / dt));
  for (int s = 1; s <= steps; ++s) {
    const double F = 1.2 * P * (s * dt) / T;
    nucleus.external_forces()[bonds] = Vec3(F, 0.0, 0.0);
    step_logged(nucleus, dt, {}, {}, log);
    if (nucleus.broken_bond_count() > 0) return F;
  }
  return std::nan("");
}

}  // namespace

std::vector<VerificationRow> run_bond_break(const VerificationCaseSpec& spec) {
  const double P = spec.get("bond_stiffness_N_m") * spec.get("bond_break_m");
  const double tol = spec.get("tolerance");
  std::vector<VerificationRow> rows;
  StepLog log1, log2;
  rows.push_back(make_row(spec, "single bond break force (N)", pull_until_break(spec, 1, log1), P,
                          tol));
  if (!log1.ok) fail_row(rows.back(), "numerical trouble in stage " + log1.stage);
  const int chain = std::max(2, static_cast<int>(std::lround(spec.get("chain_bonds"))));
  rows.push_back(make_row(spec, "chain break force (N)", pull_until_break(spec, chain, log2), P,
                          tol));
  if (!log2.ok) fail_row(rows.back(), "numerical trouble in stage " + log2.stage);
  return rows;
}

}  // namespace acdr::verification
