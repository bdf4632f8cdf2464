// buoyancy (seed Eq. 4-5): a prism of volume V held still, fully submerged in nucleus at rest
// in the open box. With bonds off the material is a viscous fluid whose pressure is a scalar
// per particle (density constraint), so at rest it is hydrostatic and pushes the prism up by
// rho g V (Archimedes); the hand holding the prism supplies F = m g - rho g V (Eq. 5 with the
// seed's sign convention: Eq. 4's buoyancy -rho g V acts against gravity).
//
// "Relaxed nucleus": the fluid starts as an unloaded lattice and must settle under its weight.
// The static end state does not depend on the viscosity, but the settling time grows with it,
// so the scene first settles at `relax_viscosity_Pa_s`, then continues with the material's own
// viscosity for `hold_s`, over whose second half the force is averaged.
#include <cmath>

#include "engine/rigid/static_scene.hpp"
#include "verification/cases.hpp"

namespace acdr::verification {

VerificationCaseSpec buoyancy_defaults(bool fast) {
  VerificationCaseSpec s;
  add_material_parameters(s, 1.0e-3);
  s.params.push_back({"box_width_m", fast ? 10.0e-3 : 14.0e-3, "m", "square box inner width"});
  s.params.push_back({"fill_depth_m", fast ? 10.0e-3 : 12.0e-3, "m", "nucleus depth"});
  s.params.push_back({"prism_size_m", 4.0e-3, "m", "cube prism edge"});
  s.params.push_back({"prism_depth_m", fast ? 3.0e-3 : 4.0e-3, "m",
                      "depth of the prism's top face below the surface"});
  s.params.push_back({"prism_mass_kg", 0.5e-3, "kg", "prism mass m_stick"});
  s.params.push_back({"relax_viscosity_Pa_s", 20.0, "Pa s", "viscosity while settling"});
  s.params.push_back({"relax_s", fast ? 0.25 : 0.4, "s", "settling time"});
  s.params.push_back({"hold_s", fast ? 0.05 : 0.1, "s", "time at the material's viscosity"});
  s.params.push_back({"tolerance", 0.05, "1", "relative tolerance"});
  return s;
}

std::vector<VerificationRow> run_buoyancy(const VerificationCaseSpec& spec) {
  const double h = spec.get("spacing_m");
  const double dt = spec.get("dt_s");
  const double rho = spec.get("density_kg_m3");
  const double g = spec.get("gravity_m_s2");
  const int nw = std::max(4, static_cast<int>(std::lround(spec.get("box_width_m") / h)));
  const int nd = std::max(4, static_cast<int>(std::lround(spec.get("fill_depth_m") / h)));
  const int np = std::max(1, static_cast<int>(std::lround(spec.get("prism_size_m") / h)));
  const int ntop = std::max(1, static_cast<int>(std::lround(spec.get("prism_depth_m") / h)));
  const double W = nw * h, D = nd * h, a = np * h;
  // Prism cells: centred laterally, top face ntop cells below the surface.
  const int i0 = (nw - np) / 2, k1 = nd - ntop, k0 = k1 - np;
  const Vec3 lo(i0 * h, i0 * h, k0 * h);
  const Vec3 hi = lo + Vec3(a, a, a);

  NucleusParticleSetup setup;
  for (int k = 0; k < nd; ++k)
    for (int j = 0; j < nw; ++j)
      for (int i = 0; i < nw; ++i) {
        if (i >= i0 && i < i0 + np && j >= i0 && j < i0 + np && k >= k0 && k < k1) continue;
        setup.positions_m.push_back(h * Vec3(i + 0.5, j + 0.5, k + 0.5));
      }
  NucleusOptions opt;
  opt.bonds_enabled = false;
  const auto box = open_box_walls(Vec3::Zero(), Vec3(W, W, D + 4.0 * h), 2.0 * h);
  Collider prism;
  prism.kind = ColliderKind::kBox;
  prism.half_extents_m = 0.5 * Vec3(a, a, a);
  prism.pose.position = 0.5 * (lo + hi);
  prism.body = 0;
  BodyReaction reaction;
  reaction.reference_point = prism.pose.position;
  StepLog log;

  // Settle at the relaxation viscosity.
  VerificationCaseSpec relax = spec;
  relax.set("viscosity_Pa_s", spec.get("relax_viscosity_Pa_s"));
  {
    Nucleus settling(nucleus_config_from(relax), solver_config_from(relax), gravity_from(relax),
                     box, setup, opt);
    const int steps = static_cast<int>(std::lround(spec.get("relax_s") / dt));
    for (int s = 0; s < steps; ++s)
      step_logged(settling, dt, std::span<const Collider>(&prism, 1),
                  std::span<BodyReaction>(&reaction, 1), log);
    const auto x = settling.positions();
    const auto v = settling.velocities();
    setup.positions_m.assign(x.begin(), x.end());
    setup.velocities_m_s.assign(v.begin(), v.end());
  }
  // Hold with the material's viscosity and average the force.
  Nucleus nucleus(nucleus_config_from(spec), solver_config_from(spec), gravity_from(spec), box,
                  setup, opt);
  const int steps = std::max(2, static_cast<int>(std::lround(spec.get("hold_s") / dt)));
  double fz = 0.0;
  int count = 0;
  for (int s = 0; s < steps; ++s) {
    step_logged(nucleus, dt, std::span<const Collider>(&prism, 1),
                std::span<BodyReaction>(&reaction, 1), log);
    if (s >= steps / 2) {
      fz += reaction.force_N.z();
      ++count;
    }
  }
  fz /= count;
  const double V = a * a * a;
  const double m = spec.get("prism_mass_kg");
  const double tol = spec.get("tolerance");
  std::vector<VerificationRow> rows;
  rows.push_back(make_row(spec, "buoyant force rho g V (N)", fz, rho * g * V, tol));
  rows.push_back(make_row(spec, "holding force m g - rho g V (N)", m * g - fz, m * g - rho * g * V,
                          tol));
  for (auto& row : rows)
    if (!log.ok) fail_row(row, "numerical trouble in stage " + log.stage);
  return rows;
}

}  // namespace acdr::verification
