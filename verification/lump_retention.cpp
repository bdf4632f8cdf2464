// lump_retention (seed Eq. 11): a lump of y particles hanging from x bonds stays when
// x k delta_max exceeds its weight y m g and falls when it does not. The lump hangs under a
// fixed layer; only the x vertical bonds to that layer can break (the lump's own bonds are
// made unbreakable, so the test is the balance of Eq. 11, not the lump's cohesion). The weight
// is ramped in slowly (quasi-static, so no dynamic overshoot) to a chosen fraction of
// x k delta_max, then held. Three rows: held at 0.8 (analytic: 1 = held), held at 1.25
// (analytic: 0 = fell), and the weight at which the bonds let go on a slow ramp past 1
// (analytic: x k delta_max).
#include <cmath>

#include "verification/cases.hpp"

namespace acdr::verification {

VerificationCaseSpec lump_retention_defaults(bool fast) {
  VerificationCaseSpec s;
  add_material_parameters(s, 1.0e-3);
  s.params.push_back({"lump_side", 3.0, "1", "lump is side x side x layers particles"});
  s.params.push_back({"lump_layers", 2.0, "1", "lump layers"});
  s.params.push_back({"ramp_s", fast ? 1.0 : 2.0, "s", "time to ramp the weight in (held rows)"});
  s.params.push_back({"release_ramp_s", fast ? 10.0 : 20.0, "s",
                      "time to ramp to 1.2 x k dmax (release row; slow = quasi-static)"});
  s.params.push_back({"hold_s", 0.5, "s", "time holding the full weight"});
  s.params.push_back({"tolerance", 0.02, "1", "relative tolerance of the critical weight"});
  return s;
}

namespace {

struct HangResult {
  bool held = false;
  double release_weight_N = std::nan("");
};

/// Hangs the lump and loads each lump particle with `ratio` of its share of x k delta_max,
/// ramped over ramp_s and held for hold_s.
HangResult hang(const VerificationCaseSpec& spec, double ratio, StepLog& log) {
  const double h = spec.get("spacing_m");
  const double dt = spec.get("dt_s");
  const double k = spec.get("bond_stiffness_N_m");
  const double dmax = spec.get("bond_break_m");
  const int n = std::max(1, static_cast<int>(std::lround(spec.get("lump_side"))));
  const int layers = std::max(1, static_cast<int>(std::lround(spec.get("lump_layers"))));
  NucleusParticleSetup setup;
  // Lump layers below z = 0; the fixed ceiling layer at z = h.
  add_lattice(setup.positions_m, Vec3(0, 0, -(layers - 1) * h), n, n, layers, h);
  const int lump = n * n * layers;
  add_lattice(setup.positions_m, Vec3(0, 0, h), n, n, 1, h);
  setup.fixed.assign(setup.positions_m.size(), 0);
  for (std::size_t i = lump; i < setup.positions_m.size(); ++i) setup.fixed[i] = 1;
  const auto& p = setup.positions_m;
  for (int i = 0; i < lump; ++i)
    for (int j = i + 1; j < lump; ++j)
      if ((p[j] - p[i]).norm() < 1.5 * h) {
        NucleusParticleSetup::Bond b;
        b.i = i;
        b.j = j;
        b.stiffness_N_m = 20.0 * k;  // a stiff, unbreakable lump: loads share equally
        b.break_stretch_m = 0.0;
        setup.bonds.push_back(b);
      }
  // The x hanging bonds: each top-layer lump particle to the fixed particle above it.
  int x = 0;
  for (int i = 0; i < lump; ++i)
    for (std::size_t j = lump; j < p.size(); ++j)
      if ((p[j] - p[i] - Vec3(0, 0, h)).norm() < 1e-9 * h) {
        NucleusParticleSetup::Bond b;
        b.i = i;
        b.j = static_cast<int>(j);
        b.stiffness_N_m = k;
        b.break_stretch_m = dmax;
        setup.bonds.push_back(b);
        ++x;
      }
  VerificationCaseSpec no_gravity = spec;
  no_gravity.set("gravity_m_s2", 0.0);  // the weight is applied as ramped external forces
  // A floor 3 h below the lump catches it when it falls.
  Collider floor;
  floor.kind = ColliderKind::kHalfSpace;
  floor.pose.position = Vec3(0, 0, -(layers + 2) * h);
  Nucleus nucleus(nucleus_config_from(spec), solver_config_from(spec), gravity_from(no_gravity),
                  std::span<const Collider>(&floor, 1), setup, NucleusOptions{});
  const double full = ratio * x * k * dmax;  // total weight to reach
  const int ramp = std::max(1, static_cast<int>(std::lround(spec.get("ramp_s") / dt)));
  const int hold = static_cast<int>(std::lround(spec.get("hold_s") / dt));
  HangResult out;
  for (int s = 1; s <= ramp + hold; ++s) {
    const double W = full * std::min(1.0, double(s) / ramp);
    for (int i = 0; i < lump; ++i) nucleus.external_forces()[i] = Vec3(0, 0, -W / lump);
    step_logged(nucleus, dt, {}, {}, log);
    if (nucleus.broken_bond_count() > 0 && std::isnan(out.release_weight_N))
      out.release_weight_N = W;
  }
  out.held = nucleus.broken_bond_count() == 0;
  return out;
}

}  // namespace

std::vector<VerificationRow> run_lump_retention(const VerificationCaseSpec& spec) {
  const int n = std::max(1, static_cast<int>(std::lround(spec.get("lump_side"))));
  const double x = n * n;
  const double strength = x * spec.get("bond_stiffness_N_m") * spec.get("bond_break_m");
  StepLog log;
  std::vector<VerificationRow> rows;
  const HangResult light = hang(spec, 0.8, log);
  rows.push_back(make_row(spec, "held at weight 0.8 x k dmax (1 = yes)", light.held ? 1.0 : 0.0,
                          1.0, 0.0));
  const HangResult heavy = hang(spec, 1.25, log);
  rows.push_back(make_row(spec, "held at weight 1.25 x k dmax (1 = yes)", heavy.held ? 1.0 : 0.0,
                          0.0, 0.0));
  VerificationCaseSpec slow = spec;
  slow.set("hold_s", 0.0);
  slow.set("ramp_s", spec.get("release_ramp_s"));
  const HangResult ramp = hang(slow, 1.2, log);
  rows.push_back(make_row(spec, "release weight x k dmax (N)", ramp.release_weight_N, strength,
                          spec.get("tolerance")));
  for (auto& row : rows)
    if (!log.ok) fail_row(row, "numerical trouble in stage " + log.stage);
  return rows;
}

}  // namespace acdr::verification
